// What `facerig-bench abi` and `facerig-bench web` share: the 14 s line a
// character speaks, the per-frame work of the C++ API and of the C ABI, the
// fastest-of-runs timer, and binding programs run as child processes that
// print their costs as JSON.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "facerig.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig::bench {

inline constexpr int kAbiPeriod = 840;  // frames in the 14 s line

// "a pa ba ma" 14 times: 14 s of speech in espeak-ng en-us names.
SpeechLine AbiBenchLine();

// Microseconds per frame: the fastest of `repeats` runs of `frames` frames.
double BestPerFrame(int frames, int repeats, const std::function<void(int)>& frame);

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
  NativeHost(const std::string& head, const SpeechLine& line);
  FrameWork Work();

 private:
  Rig rig_;
  CharacterRig character_rig_;
  Character character_;
  std::vector<float> weights_;
  std::vector<glm::vec3> positions_;
};

// The same through the C ABI.
class AbiHost {
 public:
  AbiHost(const std::string& head, const std::string& track_json);
  ~AbiHost();
  AbiHost(const AbiHost&) = delete;
  AbiHost& operator=(const AbiHost&) = delete;
  FrameWork Work();

 private:
  fr_rig* rig_ = nullptr;
  fr_speech* speech_ = nullptr;
  fr_character* character_ = nullptr;
  fr_rig_info info_{};
  std::vector<float> weights_, positions_;
};

// Runs a binding's benchmark program and parses the JSON object it prints;
// nullopt (with the reason printed) when it fails or lacks `required`.
std::optional<nlohmann::json> RunJsonProgram(const char* host, const std::string& command, const char* required);

}  // namespace facerig::bench
