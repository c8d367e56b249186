// facerig-bench: benchmarks that print a comparison in the same run and
// write JSON. Not tests: machines are noisy, so nothing here asserts a time.
#include <cstdio>
#include <string>

#include "bench_blend.h"
#include "bench_build.h"
#include "bench_register.h"
#include "bench_transfer.h"
#if FACERIG_BENCH_LIPSYNC
#include "bench_crowd.h"
#include "bench_lipsync.h"
#endif

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "blend") return RunBlendBenchmark(argc, argv);
  if (command == "transfer") return RunTransferBenchmark(argc, argv);
  if (command == "register") return RunRegisterBenchmark(argc, argv);
  if (command == "build") return RunBuildBenchmark(argc, argv);
#if FACERIG_BENCH_LIPSYNC
  if (command == "lipsync") return RunLipsyncBenchmark(argc, argv);
  if (command == "crowd") return RunCrowdBenchmark(argc, argv);
#endif
  std::fprintf(stderr,
               "usage: facerig-bench blend [--rig PATH] [--json FILE]\n"
               "       facerig-bench lipsync [--corpus FILE] [--voice V] [--rig PATH] [--json FILE]\n"
               "       facerig-bench transfer [--ict DIR] [--faces N] [--seed N] [--threads N] [--json FILE]\n"
               "       facerig-bench build [--ict DIR] [--faces N] [--seed N] [--target-vertices N] [--json FILE]\n"
               "       facerig-bench register [--ict DIR] [--faces N] [--seed N] [--target-vertices N]\n"
               "                              [--million-vertices N] [--no-million] [--json FILE]\n"
               "       facerig-bench crowd [N] [--rig PATH] [--normals] [--json FILE]\n"
               "  blend:   sparse blend job vs dense Eigen reference vs memory roofline\n"
               "  transfer: deformation transfer / displacement matrices of the ICT rig onto random identities\n"
               "  build:   the whole facerig build on re-meshed random ICT faces, each mode (issue 6)\n"
               "  register: landmarks + registration of the ICT template onto re-meshed random ICT faces (issue 5)\n"
               "  lipsync: closure, audio-visual lag, smoothness, blinks, cost (needs espeak-ng)\n"
               "  crowd:   N characters' update + blend per 60 fps frame on one core (needs espeak-ng)\n");
  return 2;
}
