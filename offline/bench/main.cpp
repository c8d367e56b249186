// facerig-bench: benchmarks that print a comparison in the same run and
// write JSON. Not tests: machines are noisy, so nothing here asserts a time.
// Each benchmark parses its own options (bench_*.cpp); this top-level app
// lists them and answers --help, --version and an unknown benchmark.
#include <string>
#include <utility>
#include <vector>

#if FACERIG_BENCH_ABI
#include "bench/abi.h"
#include "bench/web.h"
#endif
#include "bench/blend.h"
#include "bench/build.h"
#include "bench/cast.h"
#include "bench/mouth.h"
#include "bench/photo.h"
#include "bench/proportions.h"
#include "bench/register.h"
#include "bench/transfer.h"
#include "cli/options.h"
#if FACERIG_BENCH_LIPSYNC
#include "bench/align.h"
#include "bench/av_sync.h"
#include "bench/crowd.h"
#include "bench/lipsync.h"
#endif

namespace {

using Benchmark = int (*)(int, char**);

struct Entry {
  const char* name;
  const char* description;
  Benchmark run;
};

const std::vector<Entry>& Benchmarks() {
  static const std::vector<Entry> benchmarks = {
      {"blend", "sparse blend job vs dense Eigen reference vs memory roofline", RunBlendBenchmark},
      {"transfer", "deformation transfer / displacement matrices of the ICT rig onto random identities",
       RunTransferBenchmark},
      {"build", "the whole facerig build on re-meshed random ICT faces, each mode", RunBuildBenchmark},
      {"cast", "a cast of faces built in one facerig build run against one run per face", RunCastBenchmark},
      {"mouth", "ICT-FaceKit's shapes on the built-in head: the opened mouth's curtain and fold under the lower lip",
       RunMouthBenchmark},
      {"register", "landmarks + registration of the ICT template onto re-meshed random ICT faces",
       RunRegisterBenchmark},
      {"photo", "facerig photo on a 1024 px portrait with ICT-FaceKit, per step, with and without the shading fit",
       RunPhotoBenchmark},
      {"proportions", "the built-in head's face proportions (dlib's 68 points) against ICT-FaceKit's identities",
       RunProportionsBenchmark},
#if FACERIG_BENCH_ABI
      {"abi", "a character's per-frame update (and blend): C++ vs the C ABI vs Python vs C#", RunAbiBenchmark},
      {"web", "the WebAssembly module in node vs native: update (and blend) per frame, bytes to load",
       RunWebBenchmark},
#endif
#if FACERIG_BENCH_LIPSYNC
      {"lipsync", "closure, audio-visual lag, smoothness, blinks, cost (needs espeak-ng)", RunLipsyncBenchmark},
      {"crowd", "N characters' update + blend per 60 fps frame on one core (needs espeak-ng)", RunCrowdBenchmark},
      {"align", "recording-to-transcript alignment against exact truth, per voice (needs espeak-ng)",
       RunAlignBenchmark},
      {"av-sync", "the player on real recordings: mouth vs sound from the frames and the WAV (needs the player, ffmpeg)",
       RunAvSyncBenchmark},
#endif
  };
  return benchmarks;
}

}  // namespace

int main(int argc, char** argv) {
  // argv[1] names the benchmark, which parses the rest (its own --help included).
  for (const Entry& entry : Benchmarks()) {
    if (argc > 1 && std::string(argv[1]) == entry.name) return entry.run(argc, argv);
  }
  CLI::App app("facerig-bench: benchmarks that print a comparison in the same run and write JSON", "facerig-bench");
  facerig::cli::AddVersionFlag(app);
  for (const Entry& entry : Benchmarks()) app.add_subcommand(entry.name, entry.description);
  app.footer("Run 'facerig-bench BENCHMARK --help' for its options. Exit codes: 0 ok, 1 failure, 2 bad command line.");
  if (const std::optional<int> exit_code = facerig::cli::ParseSubcommandLine(app, argc, argv)) return *exit_code;
  return facerig::cli::kUsageExitCode;  // not reached: a benchmark name dispatched above
}
