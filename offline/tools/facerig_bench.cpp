// facerig-bench: benchmarks that print a comparison in the same run and
// write JSON. Not tests: machines are noisy, so nothing here asserts a time.
#include <cstdio>
#include <string>

#include "bench_blend.h"

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "blend") return RunBlendBenchmark(argc, argv);
  std::fprintf(stderr,
               "usage: facerig-bench blend [--rig PATH] [--json FILE]\n"
               "  blend: sparse blend job vs dense Eigen reference vs memory roofline\n");
  return 2;
}
