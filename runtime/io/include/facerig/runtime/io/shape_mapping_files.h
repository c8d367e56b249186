// The JSON files that override which rig shapes a viseme or an emotion moves.
// Part of facerig::runtime_io (nlohmann_json); both formats share one
// grammar: an object keyed by viseme or emotion name, each an object of
// shape name -> weight in [0,1], or shape name -> {"weight": w, ...options}.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "facerig/runtime/behaviour/emotion.h"
#include "facerig/runtime/speech/viseme_mapping.h"

namespace facerig {

// Viseme names as ToString(Viseme) ("sil", "PP", ...); option "channel":
// "jaw" | "lip". Example:
//   {"PP": {"mouthClose": 1.0, "jawOpen": 0.1}, "aa": {"jawOpen": {"weight": 0.7, "channel": "jaw"}}}
// Throws IoError naming the file and the offending field.
VisemeMappingOverrides ReadVisemeMappingFile(const std::filesystem::path& path);
// The same from text; `source` names it in errors.
VisemeMappingOverrides ParseVisemeMappingJson(std::string_view text, const std::string& source);

// Emotion names as ToString(Emotion) ("joy", ...); option "opens_lips": bool.
// Example: {"joy": {"mouthSmile_L": 0.9, "mouthSmile_R": 0.9}}.
// Throws IoError naming the file and the offending field.
EmotionOverrides ReadEmotionFile(const std::filesystem::path& path);
EmotionOverrides ParseEmotionJson(std::string_view text, const std::string& source);

}  // namespace facerig
