#include "bench/abi_hosts.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/io/rig_file.h"

namespace facerig::bench {

using Clock = std::chrono::steady_clock;

SpeechLine AbiBenchLine() {
  SpeechLine line;
  line.language.assign("en-us");
  const char* symbols[] = {"_:", "a#", "p", "A:", "b", "A:", "m", "A:", "_:"};
  const double durations[] = {0.10, 0.12, 0.04, 0.12, 0.03, 0.12, 0.05, 0.15, 0.27};
  double start = 0.0;
  for (int repeat = 0; repeat < 14; ++repeat) {
    for (int i = 0; i < 9; ++i) {
      Phoneme phoneme;
      phoneme.start = Seconds(start);
      phoneme.duration = Seconds(durations[i]);
      phoneme.symbol.assign(symbols[i]);
      line.phonemes.push_back(phoneme);
      start += durations[i];
    }
  }
  return line;
}

double BestPerFrame(int frames, int repeats, const std::function<void(int)>& frame) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    for (int i = 0; i < frames; ++i) frame(i);
    best = std::min(best, std::chrono::duration<double, std::micro>(Clock::now() - start).count() / frames);
  }
  return best;
}

NativeHost::NativeHost(const std::string& head, const SpeechLine& line)
    : rig_(LoadRig(head)),
      character_rig_(CharacterRig::Build(rig_)),
      character_(character_rig_),
      weights_(rig_.shape_count()),
      positions_(rig_.vertex_count()) {
  (void)character_.Speak(line.phonemes, Seconds(0.0));
}

FrameWork NativeHost::Work() {
  const auto update = [this](int i) {
    (void)character_.Update(Seconds((i % kAbiPeriod) / 60.0));
    std::copy(character_.weights().begin(), character_.weights().end(), weights_.begin());  // what a host reads
  };
  return {update, [this, update](int i) {
            update(i);
            (void)BlendJob{&rig_, weights_, NormalMode::kNone, positions_, {}}.Run();
          }};
}

AbiHost::AbiHost(const std::string& head, const std::string& track_json) {
  if (fr_rig_load_file(head.c_str(), &rig_) != FR_OK || fr_rig_get_info(rig_, &info_) != FR_OK ||
      fr_speech_load_track_bytes(track_json.data(), track_json.size(), &speech_) != FR_OK ||
      fr_character_create(rig_, nullptr, &character_) != FR_OK ||
      fr_character_speak(character_, speech_, 0.0) != FR_OK) {
    throw std::runtime_error(std::string("C ABI: ") + fr_last_error());
  }
  weights_.resize(info_.shape_count);
  positions_.resize(3 * std::size_t{info_.vertex_count});
}

AbiHost::~AbiHost() {
  fr_character_release(character_);
  fr_speech_release(speech_);
  fr_rig_release(rig_);
}

FrameWork AbiHost::Work() {
  const auto update = [this](int i) {
    fr_character_update(character_, (i % kAbiPeriod) / 60.0, weights_.data(), weights_.size());
  };
  return {update, [this, update](int i) {
            update(i);
            fr_rig_blend(rig_, weights_.data(), weights_.size(), FR_NORMALS_NONE, positions_.data(), nullptr,
                         info_.vertex_count);
          }};
}

std::optional<nlohmann::json> RunJsonProgram(const char* host, const std::string& command, const char* required) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1").c_str(), "r"), pclose);
  std::string output;
  char buffer[4096];
  while (pipe && std::fgets(buffer, sizeof buffer, pipe.get())) output += buffer;
  const int status = pipe ? pclose(pipe.release()) : -1;
  nlohmann::json parsed = nlohmann::json::parse(output, nullptr, false);
  if (status != 0 || !parsed.is_object() || !parsed.contains(required)) {
    std::fprintf(stderr, "%s: skipped (%s):\n%s\n", host, command.c_str(), output.c_str());
    return std::nullopt;
  }
  return parsed;
}

}  // namespace facerig::bench
