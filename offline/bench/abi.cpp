#include "bench/abi.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <stdexcept>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "facerig.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "facerig/runtime/io/rig_file.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kPeriod = 840;  // frames in the 14 s line

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
      ->check(CLI::Range(100, 10000000));
  app.add_option("--repeats", options.repeats, "runs per measurement; the fastest counts")->check(CLI::Range(1, 100));
  app.add_option("--python", options.python, "Python 3 with numpy (empty: skip Python)");
  app.add_option("--mono", options.mono, "mono (empty: skip C#)");
  app.add_option("--json", options.json, "write the results as JSON");
}

// "a pa ba ma" 14 times: 14 s of speech in espeak-ng en-us names.
facerig::SpeechLine Line() {
  facerig::SpeechLine line;
  line.language.assign("en-us");
  const char* symbols[] = {"_:", "a#", "p", "A:", "b", "A:", "m", "A:", "_:"};
  const double durations[] = {0.10, 0.12, 0.04, 0.12, 0.03, 0.12, 0.05, 0.15, 0.27};
  double start = 0.0;
  for (int repeat = 0; repeat < 14; ++repeat) {
    for (int i = 0; i < 9; ++i) {
      facerig::Phoneme phoneme;
      phoneme.start = facerig::Seconds(start);
      phoneme.duration = facerig::Seconds(durations[i]);
      phoneme.symbol.assign(symbols[i]);
      line.phonemes.push_back(phoneme);
      start += durations[i];
    }
  }
  return line;
}

// Microseconds per frame: the fastest of `repeats` runs of `frames` frames.
double BestPerFrame(int frames, int repeats, const std::function<void(int)>& frame) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    for (int i = 0; i < frames; ++i) frame(i);
    best = std::min(best, std::chrono::duration<double, std::micro>(Clock::now() - start).count() / frames);
  }
  return best;
}

struct Costs {
  double update_us = 0.0, update_blend_us = 0.0;
};

// A frame's work for one host: update alone, and update + blend.
struct FrameWork {
  std::function<void(int)> update, update_blend;
};

// The character in C++, as the C++ API's users drive it.
class NativeHost {
 public:
  NativeHost(const std::string& head, const facerig::SpeechLine& line)
      : rig_(facerig::LoadRig(head)),
        character_rig_(facerig::CharacterRig::Build(rig_)),
        character_(character_rig_),
        weights_(rig_.shape_count()),
        positions_(rig_.vertex_count()) {
    (void)character_.Speak(line.phonemes, facerig::Seconds(0.0));
  }
  FrameWork Work() {
    const auto update = [this](int i) {
      (void)character_.Update(facerig::Seconds((i % kPeriod) / 60.0));
      std::copy(character_.weights().begin(), character_.weights().end(), weights_.begin());  // what a host reads
    };
    return {update, [this, update](int i) {
              update(i);
              (void)facerig::BlendJob{&rig_, weights_, facerig::NormalMode::kNone, positions_, {}}.Run();
            }};
  }

 private:
  facerig::Rig rig_;
  facerig::CharacterRig character_rig_;
  facerig::Character character_;
  std::vector<float> weights_;
  std::vector<glm::vec3> positions_;
};

// The same through the C ABI.
class AbiHost {
 public:
  AbiHost(const std::string& head, const std::string& track_json) {
    if (fr_rig_load_file(head.c_str(), &rig_) != FR_OK || fr_rig_get_info(rig_, &info_) != FR_OK ||
        fr_speech_load_track_bytes(track_json.data(), track_json.size(), &speech_) != FR_OK ||
        fr_character_create(rig_, nullptr, &character_) != FR_OK ||
        fr_character_speak(character_, speech_, 0.0) != FR_OK) {
      throw std::runtime_error(std::string("C ABI: ") + fr_last_error());
    }
    weights_.resize(info_.shape_count);
    positions_.resize(3 * std::size_t{info_.vertex_count});
  }
  ~AbiHost() {
    fr_character_release(character_);
    fr_speech_release(speech_);
    fr_rig_release(rig_);
  }
  AbiHost(const AbiHost&) = delete;
  AbiHost& operator=(const AbiHost&) = delete;
  FrameWork Work() {
    const auto update = [this](int i) {
      fr_character_update(character_, (i % kPeriod) / 60.0, weights_.data(), weights_.size());
    };
    return {update, [this, update](int i) {
              update(i);
              fr_rig_blend(rig_, weights_.data(), weights_.size(), FR_NORMALS_NONE, positions_.data(), nullptr,
                           info_.vertex_count);
            }};
  }

 private:
  fr_rig* rig_ = nullptr;
  fr_speech* speech_ = nullptr;
  fr_character* character_ = nullptr;
  fr_rig_info info_{};
  std::vector<float> weights_, positions_;
};

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
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1").c_str(), "r"), pclose);
  std::string output;
  char buffer[4096];
  while (pipe && std::fgets(buffer, sizeof buffer, pipe.get())) output += buffer;
  const int status = pipe ? pclose(pipe.release()) : -1;
  const nlohmann::json parsed = nlohmann::json::parse(output, nullptr, false);
  if (status != 0 || !parsed.is_object() || !parsed.contains("update_us")) {
    std::fprintf(stderr, "%s: skipped (%s):\n%s\n", host, command.c_str(), output.c_str());
    return std::nullopt;
  }
  return Costs{parsed["update_us"].get<double>(), parsed["update_blend_us"].get<double>()};
}

std::string Quote(const std::string& text) { return "'" + text + "'"; }

int Run(const AbiOptions& options) {
  try {
    const facerig::SpeechLine line = Line();
    const std::string track_json = facerig::FormatPhonemeTrack(line);
    const std::filesystem::path track = std::filesystem::temp_directory_path() / "facerig_bench_abi_track.json";
    facerig::WriteFileAtomically(track, track_json);
    const std::string args = " " + Quote(options.head) + " " + Quote(track.string()) + " " +
                             std::to_string(options.frames) + " " + std::to_string(options.repeats);
    std::vector<std::pair<std::string, std::optional<Costs>>> hosts;
    const auto [native_costs, abi_costs] = InProcess(options, line, track_json);
    hosts.emplace_back("C++ (facerig::Character)", native_costs);
    hosts.emplace_back("C ABI (libfacerig)", abi_costs);
    if (!options.python.empty()) {
      hosts.emplace_back("Python (ctypes + numpy)",
                         External("Python", "FACERIG_LIBRARY_DIR=" + Quote(FACERIG_BENCH_LIB_DIR) + " PYTHONPATH=" +
                                                Quote(FACERIG_BENCH_PYTHON_DIR) + " " + Quote(options.python) + " " +
                                                Quote(FACERIG_BENCH_PYTHON_DIR "/benchmarks/abi_frames.py") + args));
    }
    if (!options.mono.empty()) {
      hosts.emplace_back("C# (Mono, P/Invoke)",
                         External("C#", "LD_LIBRARY_PATH=" + Quote(FACERIG_BENCH_LIB_DIR) + " " + Quote(options.mono) +
                                            " " + Quote(FACERIG_BENCH_CSHARP_DIR "/AbiBench.exe") + args));
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
