#include "facerig/runtime/speech/viseme.h"

#include <array>

namespace facerig {
namespace {
constexpr std::array<std::string_view, kVisemeCount> kNames = {
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
}  // namespace

std::string_view ToString(Viseme viseme) {
  const auto index = static_cast<std::size_t>(viseme);
  return index < kNames.size() ? kNames[index] : std::string_view("?");
}

std::optional<Viseme> ParseViseme(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<Viseme>(i);
  }
  return std::nullopt;
}

}  // namespace facerig
