// facerig-bench build: the whole pipeline (`facerig build`) on random
// re-meshed ICT faces (tests/support/registration_targets.h): landmarks ->
// registration -> transfer -> the target's own vertices, timed end to end,
// with each mode's relative error and leak against the known answer, printed
// against its targets.
#pragma once

int RunBuildBenchmark(int argc, char** argv);
