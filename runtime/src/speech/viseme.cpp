#include "facerig/runtime/speech/viseme.h"

#include <array>

#include "facerig/runtime/enum_names.h"

namespace facerig {
namespace {
constexpr std::array<std::string_view, kVisemeCount> kNames = {
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
}  // namespace

std::string_view ToString(Viseme viseme) { return EnumName(kNames, viseme); }

std::optional<Viseme> ParseViseme(std::string_view name) { return EnumNamed<Viseme>(kNames, name); }

}  // namespace facerig
