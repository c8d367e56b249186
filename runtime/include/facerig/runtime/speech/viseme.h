// The 15 visemes of the Oculus / MPEG-4 set.
#pragma once

#include <cstdint>
#include <cstddef>
#include <optional>
#include <string_view>

#include "facerig/runtime/seconds.h"

namespace facerig {

enum class Viseme : std::uint8_t {
  kSil,  // silence, mouth at rest
  kPP,   // p b m: lips closed
  kFF,   // f v: lower lip to upper teeth
  kTH,   // th: tongue between the teeth
  kDD,   // t d
  kKK,   // k g
  kCH,   // tS dZ S Z
  kSS,   // s z
  kNN,   // n l
  kRR,   // r
  kAA,   // a
  kE,    // e
  kIH,   // i
  kOH,   // o
  kOU,   // u
};

inline constexpr std::size_t kVisemeCount = 15;

// "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou".
std::string_view ToString(Viseme viseme);
std::optional<Viseme> ParseViseme(std::string_view name);

// The Oculus / Meta viseme morph-target name: "viseme_sil", "viseme_PP", ...,
// "viseme_aa", "viseme_E", "viseme_I", "viseme_O", "viseme_U".
std::string_view OculusTargetName(Viseme viseme);

// The viseme a per-viseme target's name stands for: "viseme_PP", "PP",
// "visemePP", "viseme_ih" or Oculus' "viseme_I", in any case and behind a
// namespace ("blendShape1.viseme_aa"); nullopt for any other name.
std::optional<Viseme> VisemeOfTargetName(std::string_view name);

}  // namespace facerig

namespace facerig {

// One viseme target in time, made from one phoneme (or half of a diphthong).
struct VisemeKey {
  Seconds start{0.0};
  Seconds end{0.0};  // end >= start (end == start for zero-length events)
  Viseme viseme = Viseme::kSil;
  // Stress / emphasis in [0,1] (1 = full articulation), e.g. lower for
  // unstressed function-word vowels.
  float strength = 1.0f;
};

}  // namespace facerig
