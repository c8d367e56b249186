#include "bench/abi.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/abi_hosts.h"
#include "bench/common.h"
#include "cli/options.h"
#include "bench/json.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/phoneme_track_file.h"

namespace {

using facerig::bench::AbiHost;
using facerig::bench::BestPerFrame;
using facerig::bench::Costs;
using facerig::bench::FrameWork;
using facerig::bench::NativeHost;

struct AbiOptions {
  std::string head = FACERIG_DEFAULT_HEAD;
  std::string python = FACERIG_BENCH_PYTHON;
  std::string mono = FACERIG_BENCH_MONO;
  int frames = 20000;
  int repeats = 5;
  std::string json;
};

void AddAbiOptions(CLI::App& app, AbiOptions& options) {
  app.add_option("--rig", options.head, "the rig (default: the built-in head)");
  app.add_option("--frames", options.frames, "frames per run of update (a tenth of them for update + blend)")
      ->check(facerig::cli::InRange(100, 10000000));
  app.add_option("--repeats", options.repeats, "runs per measurement; the fastest counts")->check(facerig::cli::InRange(1, 100));
  app.add_option("--python", options.python, "Python 3 with numpy (empty: skip Python)");
  app.add_option("--mono", options.mono, "mono (empty: skip C#)");
  app.add_option("--json", options.json, "write the results as JSON");
}

// C++ and the C ABI measured in alternation, so that both see the same
// machine load; each the fastest of its runs.
std::pair<Costs, Costs> InProcess(const AbiOptions& options, const facerig::SpeechLine& line,
                                  const std::string& track_json) {
  NativeHost native(options.head, line);
  AbiHost abi(options.head, track_json);
  FrameWork works[2] = {native.Work(), abi.Work()};
  Costs costs[2] = {{1e300, 1e300}, {1e300, 1e300}};
  for (int r = 0; r < options.repeats; ++r) {
    for (int host = 0; host < 2; ++host) {
      costs[host].update_us = std::min(costs[host].update_us, BestPerFrame(options.frames, 1, works[host].update));
      costs[host].update_blend_us =
          std::min(costs[host].update_blend_us, BestPerFrame(options.frames / 10, 1, works[host].update_blend));
    }
  }
  return {costs[0], costs[1]};
}

// Runs a binding's benchmark program; nullopt (with the reason printed) when it fails.
std::optional<Costs> External(const char* host, const std::string& command) {
  const std::optional<nlohmann::json> parsed = facerig::bench::RunJsonProgram(host, command, "update_us");
  if (!parsed) return std::nullopt;
  return Costs{(*parsed)["update_us"].get<double>(), (*parsed)["update_blend_us"].get<double>()};
}

int Run(const AbiOptions& options) {
  try {
    const facerig::SpeechLine line = facerig::bench::AbiBenchLine();
    const std::string track_json = facerig::FormatPhonemeTrack(line);
    const std::filesystem::path track = std::filesystem::temp_directory_path() / "facerig_bench_abi_track.json";
    facerig::WriteFileAtomically(track, track_json);
    const std::string args = " " + ShellQuote(options.head) + " " + ShellQuote(track.string()) + " " +
                             std::to_string(options.frames) + " " + std::to_string(options.repeats);
    std::vector<std::pair<std::string, std::optional<Costs>>> hosts;
    const auto [native_costs, abi_costs] = InProcess(options, line, track_json);
    hosts.emplace_back("C++ (facerig::Character)", native_costs);
    hosts.emplace_back("C ABI (libfacerig)", abi_costs);
    if (!options.python.empty()) {
      hosts.emplace_back("Python (ctypes + numpy)",
                         External("Python", "FACERIG_LIBRARY_DIR=" + ShellQuote(FACERIG_BENCH_LIB_DIR) +
                                                " PYTHONPATH=" + ShellQuote(FACERIG_BENCH_PYTHON_DIR) + " " +
                                                ShellQuote(options.python) + " " +
                                                ShellQuote(FACERIG_BENCH_PYTHON_DIR "/benchmarks/abi_frames.py") + args));
    }
    if (!options.mono.empty()) {
      hosts.emplace_back("C# (Mono, P/Invoke)",
                         External("C#", "LD_LIBRARY_PATH=" + ShellQuote(FACERIG_BENCH_LIB_DIR) + " " +
                                            ShellQuote(options.mono) + " " +
                                            ShellQuote(FACERIG_BENCH_CSHARP_DIR "/AbiBench.exe") + args));
    }
    std::filesystem::remove(track);

    const Costs native = *hosts.front().second;
    std::printf("per frame on %s, one character (fastest of %d runs; update: %d frames, + blend: %d):\n",
                options.head.c_str(), options.repeats, options.frames, options.frames / 10);
    std::printf("  %-26s %12s %12s %16s\n", "host", "update us", "overhead us", "update+blend us");
    nlohmann::json report = {{"benchmark", "abi"}, {"rig", options.head}, {"frames", options.frames},
                             {"repeats", options.repeats}, {"hosts", nlohmann::json::array()}};
    for (const auto& [name, costs] : hosts) {
      if (!costs) continue;
      std::printf("  %-26s %12.3f %12.3f %16.1f\n", name.c_str(), costs->update_us,
                  costs->update_us - native.update_us, costs->update_blend_us);
      report["hosts"].push_back({{"host", name},
                                 {"update_us", costs->update_us},
                                 {"overhead_us", costs->update_us - native.update_us},
                                 {"update_blend_us", costs->update_blend_us}});
    }
    return WriteBenchJson(options.json, report);
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunAbiBenchmark(int argc, char** argv) {
  return ParseAndRunBench<AbiOptions>(argc, argv,
                                      "The per-frame cost of a character's update, and of update + blend, called "
                                      "natively in C++, through the C ABI, from Python and from C#",
                                      "facerig-bench abi", AddAbiOptions, Run);
}
