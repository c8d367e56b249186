// What a rig cannot do as a talking face: speak (no mouth, jaw or viseme
// shapes the viseme mapping can use) or blink (no eyeBlink shapes). Checked
// once per rig; the player and `facerig inspect` print the warnings and the
// JSON reports list them, so a rig that stays silently still says why.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

struct RigWarning {
  std::string code;     // "cannot_speak" or "cannot_blink", for reports
  std::string message;  // one line, for people
};

inline constexpr std::string_view kCannotSpeak = "cannot_speak";
inline constexpr std::string_view kCannotBlink = "cannot_blink";

// The rig's speech and blink warnings, in that order; empty when it can do both.
std::vector<RigWarning> SpeechAndBlinkWarnings(const Rig& rig);

}  // namespace facerig
