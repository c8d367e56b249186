#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/mtl.h"
#include "text_lines.h"

namespace facerig {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view Trim(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

// Next whitespace-separated word of `rest` (advancing it); empty at the end.
std::string_view NextToken(std::string_view& rest) {
  rest = Trim(rest);
  std::size_t end = 0;
  while (end < rest.size() && !IsSpace(rest[end])) ++end;
  const std::string_view token = rest.substr(0, end);
  rest.remove_prefix(end);
  return token;
}

bool EqualsIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x >= 'A' && x <= 'Z' ? x - 'A' + 'a' : x) == (y >= 'A' && y <= 'Z' ? y - 'A' + 'a' : y);
         });
}

bool EndsWithIgnoringCase(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() && EqualsIgnoringCase(text.substr(text.size() - suffix.size()), suffix);
}

std::optional<float> ToFloat(std::string_view token) {
  float value = 0.0f;
  const char* first = token.data();
  if (!token.empty() && token.front() == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), value);
  if (token.empty() || ptr != token.data() + token.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return INFINITY;
  if (ec != std::errc()) return std::nullopt;
  return value;
}

// How many words follow a map option: -o, -s and -t take one to three
// numbers, the rest exactly the count below. An unknown option takes the
// numbers that follow it.
int OptionArgumentCount(std::string_view option) {
  for (std::string_view one : {"-blendu", "-blendv", "-boost", "-cc", "-clamp", "-texres", "-bm", "-imfchan", "-type"}) {
    if (EqualsIgnoringCase(option, one)) return 1;
  }
  if (EqualsIgnoringCase(option, "-mm")) return 2;
  return -1;  // numbers, as many as there are (at most 3)
}

class MtlParser {
 public:
  MtlParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  std::vector<MtlMaterial> Parse() {
    ForEachLine(text_, [this](std::string_view line) {
      ++line_;
      ParseLine(line);
    });
    for (MtlMaterial& material : materials_) Finish(material);
    return std::move(materials_);
  }

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message, line_);
  }

  float Number(std::string_view token, const char* what) const {
    const std::optional<float> value = ToFloat(token);
    if (!value) Fail(IoErrorKind::kParse, std::string(what) + ": expected a number, found '" + QuoteInput(token, 40) + "'");
    if (!std::isfinite(*value)) Fail(IoErrorKind::kNonFinite, std::string(what) + ": non-finite number '" + QuoteInput(token, 40) + "'");
    return *value;
  }

  MtlMaterial& Current(std::string_view keyword) {
    if (materials_.empty()) Fail(IoErrorKind::kParse, "'" + QuoteInput(keyword, 40) + "' before any newmtl");
    return materials_.back();
  }

  void ParseLine(std::string_view line) {
    std::string_view rest = line;
    const std::string_view keyword = NextToken(rest);
    if (keyword.empty() || keyword.front() == '#') return;
    if (EqualsIgnoringCase(keyword, "newmtl")) {
      const std::string_view name = Trim(rest);
      if (name.empty()) Fail(IoErrorKind::kParse, "newmtl without a name");
      materials_.push_back({.material = Material{.name = std::string(name)}});
      has_d_.push_back(false);
    } else if (EqualsIgnoringCase(keyword, "Kd")) {
      ParseColour(rest, Current(keyword));
    } else if (EqualsIgnoringCase(keyword, "d")) {
      Current(keyword).material.base_colour.a = std::clamp(Number(NextToken(rest), "d"), 0.0f, 1.0f);
      has_d_.back() = true;
    } else if (EqualsIgnoringCase(keyword, "Tr")) {
      MtlMaterial& material = Current(keyword);
      const float transparency = std::clamp(Number(NextToken(rest), "Tr"), 0.0f, 1.0f);
      if (!has_d_.back()) material.material.base_colour.a = 1.0f - transparency;
    } else if (EqualsIgnoringCase(keyword, "Ns")) {
      const float exponent = std::max(Number(NextToken(rest), "Ns"), 0.0f);
      Current(keyword).material.roughness = std::sqrt(2.0f / (exponent + 2.0f));
    } else if (EqualsIgnoringCase(keyword, "map_Kd")) {
      Current(keyword).base_colour_map = ParseMap(rest, keyword);
    } else if (EqualsIgnoringCase(keyword, "map_Bump") || EqualsIgnoringCase(keyword, "bump") ||
               EqualsIgnoringCase(keyword, "norm")) {
      Current(keyword).normal_map = ParseMap(rest, keyword);
    }
  }

  // `Kd r g b` or `Kd r` (grey); `Kd spectral` and `Kd xyz` keep the default.
  void ParseColour(std::string_view rest, MtlMaterial& material) {
    std::string_view first = NextToken(rest);
    if (EqualsIgnoringCase(first, "spectral") || EqualsIgnoringCase(first, "xyz")) return;
    if (first.empty()) Fail(IoErrorKind::kParse, "Kd needs a colour");
    const float red = Number(first, "Kd");
    const std::string_view green = NextToken(rest);
    const std::string_view blue = NextToken(rest);
    if (!green.empty() && blue.empty()) Fail(IoErrorKind::kParse, "Kd needs 1 or 3 numbers");
    glm::vec4& colour = material.material.base_colour;
    colour.r = red;
    colour.g = green.empty() ? red : Number(green, "Kd");
    colour.b = blue.empty() ? red : Number(blue, "Kd");
    for (int i = 0; i < 3; ++i) colour[i] = std::clamp(colour[i], 0.0f, 1.0f);
  }

  // Options, then the file name: the rest of the line.
  MtlMap ParseMap(std::string_view rest, std::string_view keyword) {
    for (rest = Trim(rest); rest.starts_with('-');) {
      std::string_view after = rest;
      const std::string_view option = NextToken(after);
      const int count = OptionArgumentCount(option);
      for (int i = 0; count < 0 ? i < 3 : i < count; ++i) {
        std::string_view next = after;
        const std::string_view argument = NextToken(next);
        if (argument.empty() || (count < 0 && !ToFloat(argument))) break;
        after = next;
      }
      rest = Trim(after);
    }
    if (rest.empty()) Fail(IoErrorKind::kParse, QuoteInput(keyword, 40) + " without a file name");
    std::string file(rest);
    std::replace(file.begin(), file.end(), '\\', '/');
    return {std::move(file), std::string(keyword), line_};
  }

  static void Finish(MtlMaterial& material) {
    if (material.material.base_colour.a < 1.0f) material.material.alpha_mode = AlphaMode::kBlend;
  }

  std::string_view text_;
  const std::string& path_;
  std::int64_t line_ = 0;
  std::vector<MtlMaterial> materials_;
  std::vector<bool> has_d_;  // per material: `d` given, which wins over `Tr`
};

}  // namespace

std::vector<MtlMaterial> ParseMtl(std::string_view text, const std::string& path_for_errors) {
  return MtlParser(text, path_for_errors).Parse();
}

std::vector<std::string> SplitMtllibNames(std::string_view rest_of_line) {
  std::vector<std::string> names;
  bool all_mtl = true;
  for (std::string_view rest = rest_of_line, word = NextToken(rest); !word.empty(); word = NextToken(rest)) {
    all_mtl = all_mtl && EndsWithIgnoringCase(word, ".mtl");
    names.emplace_back(word);
  }
  if (!all_mtl) names = {std::string(Trim(rest_of_line))};
  for (std::string& name : names) std::replace(name.begin(), name.end(), '\\', '/');
  return names;
}

}  // namespace facerig
