#include "facerig/runtime/io/shape_mapping_files.h"

#include <cmath>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

// Mapping files are a few kilobytes; refuse anything absurd before parsing.
constexpr std::size_t kMaxMappingFileBytes = 16u << 20;

[[noreturn]] void Fail(const std::string& source, const std::string& field, const std::string& what) {
  throw IoError(IoErrorKind::kParse, source, field + ": " + what);
}

// One "shape": weight entry; `options` is the entry's object when it has one.
struct ShapeWeightEntry {
  std::string shape;
  float weight = 0.0f;
  const nlohmann::json* options = nullptr;
  std::string field;  // "key.shape", for errors
};

// The shared grammar. `parse_key` maps a top-level key to its index (or
// nullopt); `key_kind` and `expected_keys` word the error for an unknown one.
// `on_entries` receives each key's index and entries, in file order.
void ParseShapeWeights(std::string_view text, const std::string& source, const char* key_kind,
                       const char* expected_keys, const std::function<std::optional<std::size_t>(std::string_view)>& parse_key,
                       const std::function<void(std::size_t, std::vector<ShapeWeightEntry>&)>& on_entries) {
  CheckJsonNesting(text, source);
  const nlohmann::json json = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
  if (json.is_discarded()) throw IoError(IoErrorKind::kParse, source, "not valid JSON");
  if (!json.is_object()) {
    throw IoError(IoErrorKind::kParse, source, std::string("expected an object keyed by ") + key_kind + " name");
  }
  for (const auto& [key, shapes] : json.items()) {
    const std::optional<std::size_t> index = parse_key(key);
    if (!index) Fail(source, key, std::string("unknown ") + key_kind + " (expected " + expected_keys + ")");
    if (!shapes.is_object()) Fail(source, key, "expected an object of shape name -> weight");
    std::vector<ShapeWeightEntry> entries;
    for (const auto& [shape, value] : shapes.items()) {
      ShapeWeightEntry entry{shape, 0.0f, nullptr, key + "." + shape};
      const nlohmann::json* weight = &value;
      if (value.is_object()) {
        const auto w = value.find("weight");
        if (w == value.end()) Fail(source, entry.field, "missing \"weight\"");
        weight = &*w;
        entry.options = &value;
      }
      if (!weight->is_number()) Fail(source, entry.field, "weight is not a number");
      const double w = weight->get<double>();
      if (!std::isfinite(w) || w < 0.0 || w > 1.0) Fail(source, entry.field, "weight outside [0,1]");
      entry.weight = static_cast<float>(w);
      entries.push_back(std::move(entry));
    }
    on_entries(*index, entries);
  }
}

std::optional<MappingChannel> ParseChannel(const ShapeWeightEntry& entry, const std::string& source) {
  if (entry.options == nullptr) return std::nullopt;
  const auto ch = entry.options->find("channel");
  if (ch == entry.options->end()) return std::nullopt;
  const std::string field = entry.field + ".channel";
  if (!ch->is_string()) Fail(source, field, "expected \"jaw\" or \"lip\"");
  const std::string name = ch->get<std::string>();
  if (name == "jaw") return MappingChannel::kJaw;
  if (name == "lip") return MappingChannel::kLip;
  Fail(source, field, "expected \"jaw\" or \"lip\", got \"" + name + "\"");
}

std::optional<bool> ParseOpensLips(const ShapeWeightEntry& entry, const std::string& source) {
  if (entry.options == nullptr) return std::nullopt;
  const auto o = entry.options->find("opens_lips");
  if (o == entry.options->end()) return std::nullopt;
  if (!o->is_boolean()) Fail(source, entry.field + ".opens_lips", "expected true or false");
  return o->get<bool>();
}

template <typename Enum>
std::optional<std::size_t> IndexOf(std::optional<Enum> value) {
  return value ? std::optional<std::size_t>(static_cast<std::size_t>(*value)) : std::nullopt;
}

}  // namespace

VisemeMappingOverrides ParseVisemeMappingJson(std::string_view text, const std::string& source) {
  VisemeMappingOverrides overrides;
  ParseShapeWeights(
      text, source, "viseme", "sil, PP, FF, TH, DD, kk, CH, SS, nn, RR, aa, E, ih, oh, ou",
      [](std::string_view key) { return IndexOf(ParseViseme(key)); },
      [&](std::size_t viseme, std::vector<ShapeWeightEntry>& entries) {
        std::vector<NamedShapeWeight> list;
        for (ShapeWeightEntry& e : entries) list.push_back({std::move(e.shape), e.weight, ParseChannel(e, source)});
        overrides.visemes[viseme] = std::move(list);
      });
  return overrides;
}

VisemeMappingOverrides ReadVisemeMappingFile(const std::filesystem::path& path) {
  return ParseVisemeMappingJson(ReadInputText(path, kMaxMappingFileBytes), path.string());
}

EmotionOverrides ParseEmotionJson(std::string_view text, const std::string& source) {
  EmotionOverrides overrides;
  ParseShapeWeights(
      text, source, "emotion", "joy, sadness, fear, anger, surprise, disgust",
      [](std::string_view key) { return IndexOf(ParseEmotion(key)); },
      [&](std::size_t emotion, std::vector<ShapeWeightEntry>& entries) {
        std::vector<NamedEmotionWeight> list;
        for (ShapeWeightEntry& e : entries) list.push_back({std::move(e.shape), e.weight, ParseOpensLips(e, source)});
        overrides.emotions[emotion] = std::move(list);
      });
  return overrides;
}

EmotionOverrides ReadEmotionFile(const std::filesystem::path& path) {
  return ParseEmotionJson(ReadInputText(path, kMaxMappingFileBytes), path.string());
}

}  // namespace facerig
