// facerig-bench abi: the per-frame cost of a character's update (and of
// update + blend) called natively in C++, through the C ABI (libfacerig),
// from Python (ctypes) and from C# (Mono), in one run on the built-in head.
#pragma once

int RunAbiBenchmark(int argc, char** argv);
