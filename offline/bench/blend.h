// facerig-bench blend: sparse BlendJob vs a dense Eigen reference vs the
// memory roofline, on one rig.
#pragma once

int RunBlendBenchmark(int argc, char** argv);
