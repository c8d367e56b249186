// facerig-bench crowd N: N characters speaking different lines; per frame the
// runtime update and blend evaluation of every character, on one core.
#pragma once

int RunCrowdBenchmark(int argc, char** argv);
