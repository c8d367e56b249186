#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/speech/viseme.h"

#include <array>
#include <cctype>
#include <string>

#include "facerig/runtime/enum_names.h"

namespace facerig {
namespace {
constexpr std::array<std::string_view, kVisemeCount> kNames = {
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
constexpr std::array<std::string_view, kVisemeCount> kOculusTargets = {
    "viseme_sil", "viseme_PP", "viseme_FF", "viseme_TH", "viseme_DD", "viseme_kk", "viseme_CH", "viseme_SS",
    "viseme_nn",  "viseme_RR", "viseme_aa", "viseme_E",  "viseme_I",  "viseme_O",  "viseme_U"};

}  // namespace

std::string_view ToString(Viseme viseme) { return EnumName(kNames, viseme); }

std::optional<Viseme> ParseViseme(std::string_view name) { return EnumNamed<Viseme>(kNames, name); }

std::string_view OculusTargetName(Viseme viseme) { return EnumName(kOculusTargets, viseme); }

std::optional<Viseme> VisemeOfTargetName(std::string_view name) {
  if (const std::size_t prefix = name.find_last_of(".:|"); prefix != std::string_view::npos) {
    name.remove_prefix(prefix + 1);
  }
  if (name.size() > 6 && EqualIgnoringAsciiCase(name.substr(0, 6), "viseme")) {
    name.remove_prefix(6);
    if (name.starts_with('_')) name.remove_prefix(1);
  }
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const std::string_view oculus_short = kOculusTargets[v].substr(7);  // "I", "O", "U" for ih, oh, ou
    if (EqualIgnoringAsciiCase(name, kNames[v]) || EqualIgnoringAsciiCase(name, oculus_short)) return static_cast<Viseme>(v);
  }
  return std::nullopt;
}

}  // namespace facerig
