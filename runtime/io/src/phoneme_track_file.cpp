#include "facerig/runtime/io/phoneme_track_file.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

using Json = nlohmann::json;

constexpr std::string_view kFormatName = "facerig-phoneme-track";

// One step of a JSON pointer: an object key, or an array index when key is empty.
struct PathStep {
  std::string key;
  std::size_t index = 0;
};
using JsonPath = std::vector<PathStep>;

std::string PointerString(const JsonPath& path) {
  std::string pointer;
  for (const PathStep& step : path) {
    pointer += '/';
    pointer += step.key.empty() ? std::to_string(step.index) : step.key;
  }
  return pointer.empty() ? "/" : pointer;
}

// The 1-based line on which the value at `path` starts in `text`, or 0.
// nlohmann::json keeps no positions, so this re-scans the (already valid)
// text, tracking only the container structure.
std::int64_t LineOf(std::string_view text, const JsonPath& path) {
  struct Frame {
    bool array = false;
    bool expect_key = false;
    std::size_t index = 0;
    std::string key;
  };
  std::vector<Frame> stack;
  std::int64_t line = 1;
  auto matches = [&] {
    if (stack.size() != path.size()) return false;
    for (std::size_t i = 0; i < stack.size(); ++i) {
      if (stack[i].array ? !path[i].key.empty() || path[i].index != stack[i].index
                         : path[i].key != stack[i].key) {
        return false;
      }
    }
    return true;
  };
  auto skip_string = [&](std::size_t& i, std::string* out) {
    for (++i; i < text.size() && text[i] != '"'; ++i) {
      if (text[i] == '\\') {
        ++i;
        if (out && i < text.size()) out->push_back(text[i]);
      } else if (out) {
        out->push_back(text[i]);
      }
    }
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == ' ' || c == '\t' || c == '\r') {
    } else if (c == ',') {
      if (!stack.empty()) {
        if (stack.back().array) {
          ++stack.back().index;
        } else {
          stack.back().expect_key = true;
        }
      }
    } else if (c == ':') {
      if (!stack.empty()) stack.back().expect_key = false;
    } else if (c == '}' || c == ']') {
      if (!stack.empty()) stack.pop_back();
    } else if (!stack.empty() && !stack.back().array && stack.back().expect_key && c == '"') {
      stack.back().key.clear();
      skip_string(i, &stack.back().key);
    } else {
      if (matches()) return line;
      if (c == '{') {
        stack.push_back({false, true, 0, {}});
      } else if (c == '[') {
        stack.push_back({true, false, 0, {}});
      } else if (c == '"') {
        skip_string(i, nullptr);
      } else {
        while (i + 1 < text.size() && text[i + 1] != ',' && text[i + 1] != '}' &&
               text[i + 1] != ']' && text[i + 1] != '\n' && text[i + 1] != ' ') {
          ++i;
        }
      }
    }
  }
  return 0;
}

class TrackReader {
 public:
  TrackReader(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  [[noreturn]] void Fail(IoErrorKind kind, const JsonPath& at, const std::string& message) const {
    throw IoError(kind, path_, PointerString(at) + ": " + message, LineOf(text_, at));
  }

  const Json& Field(const Json& object, const JsonPath& at, const char* name) const {
    const auto it = object.find(name);
    if (it == object.end()) Fail(IoErrorKind::kParse, at, std::string("missing \"") + name + "\"");
    return *it;
  }

  std::string String(const Json& value, const JsonPath& at, std::size_t max_bytes,
                     const char* what) const {
    if (!value.is_string()) Fail(IoErrorKind::kParse, at, std::string(what) + " is not a string");
    const std::string& s = value.get_ref<const std::string&>();
    if (s.size() > max_bytes) {
      Fail(IoErrorKind::kParse, at,
           std::string(what) + " is " + std::to_string(s.size()) + " bytes long (at most " +
               std::to_string(max_bytes) + ")");
    }
    if (s.find('\0') != std::string::npos) {
      Fail(IoErrorKind::kParse, at, std::string(what) + " contains a NUL character");
    }
    return s;
  }

  double Time(const Json& value, const JsonPath& at, const char* what) const {
    if (!value.is_number()) Fail(IoErrorKind::kParse, at, std::string(what) + " is not a number");
    const double t = value.get<double>();
    if (!std::isfinite(t)) Fail(IoErrorKind::kNonFinite, at, std::string(what) + " is not finite");
    if (t < 0.0) Fail(IoErrorKind::kNonFinite, at, std::string(what) + " is negative");
    if (t > kPhonemeTrackMaxSeconds) {
      Fail(IoErrorKind::kAbsurdCount, at, std::string(what) + " is over 24 hours");
    }
    return t;
  }

  PhonemeTrack Read() const {
    Json json;
    try {
      json = Json::parse(text_.begin(), text_.end());
    } catch (const Json::parse_error& e) {
      const std::size_t byte = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text_.size());
      std::int64_t line = 1;
      for (std::size_t i = 0; i < byte; ++i) line += text_[i] == '\n';
      throw IoError(IoErrorKind::kParse, path_, std::string("malformed JSON: ") + e.what(), line,
                    static_cast<std::int64_t>(byte));
    } catch (const Json::out_of_range& e) {
      throw IoError(IoErrorKind::kNonFinite, path_, std::string("number out of range: ") + e.what());
    }
    const JsonPath root;
    if (!json.is_object()) Fail(IoErrorKind::kParse, root, "not a JSON object");

    if (const auto it = json.find("format"); it != json.end()) {
      if (!it->is_string() || it->get_ref<const std::string&>() != kFormatName) {
        Fail(IoErrorKind::kBadMagic, {{"format", 0}},
             "format is not \"" + std::string(kFormatName) + "\"");
      }
    }
    const Json& version = Field(json, root, "version");
    if (!version.is_number_integer()) Fail(IoErrorKind::kParse, {{"version", 0}}, "not an integer");
    if (version.get<std::int64_t>() != kPhonemeTrackVersion) {
      Fail(IoErrorKind::kUnsupportedVersion, {{"version", 0}},
           "version " + version.dump() + " (this build reads version " +
               std::to_string(kPhonemeTrackVersion) + ")");
    }

    PhonemeTrack track;
    SpeechLine& line = track.line;
    if (const auto it = json.find("text"); it != json.end()) {
      line.text = String(*it, {{"text", 0}}, kPhonemeTrackMaxTextBytes, "text");
    }
    line.language.assign(
        String(Field(json, root, "language"), {{"language", 0}}, 15, "language"));
    if (const auto it = json.find("audio"); it != json.end()) {
      track.audio_path = String(*it, {{"audio", 0}}, 4096, "audio path");
    }

    const Json& phonemes = Field(json, root, "phonemes");
    const JsonPath phonemes_path = {{"phonemes", 0}};
    if (!phonemes.is_array()) Fail(IoErrorKind::kParse, phonemes_path, "not an array");
    if (phonemes.size() > kPhonemeTrackMaxPhonemes) {
      Fail(IoErrorKind::kAbsurdCount, phonemes_path,
           std::to_string(phonemes.size()) + " phonemes (at most " +
               std::to_string(kPhonemeTrackMaxPhonemes) + ")");
    }
    line.phonemes.reserve(phonemes.size());
    for (std::size_t i = 0; i < phonemes.size(); ++i) {
      const Json& item = phonemes[i];
      JsonPath at = phonemes_path;
      at.push_back({{}, i});
      if (!item.is_object()) Fail(IoErrorKind::kParse, at, "phoneme is not an object");
      auto field_path = [&](const char* name) {
        JsonPath p = at;
        p.push_back({name, 0});
        return p;
      };
      Phoneme phoneme;
      phoneme.start = Seconds(Time(Field(item, at, "start"), field_path("start"), "start"));
      phoneme.duration = Seconds(Time(Field(item, at, "duration"), field_path("duration"), "duration"));
      const std::string symbol =
          String(Field(item, at, "symbol"), field_path("symbol"), 8, "symbol");
      if (symbol.empty()) Fail(IoErrorKind::kParse, field_path("symbol"), "symbol is empty");
      phoneme.symbol.assign(symbol);
      if (const auto it = item.find("language"); it != item.end()) {
        phoneme.language.assign(String(*it, field_path("language"), 15, "language"));
      } else {
        phoneme.language = line.language;
      }
      if (const auto it = item.find("word_start"); it != item.end()) {
        if (!it->is_boolean()) Fail(IoErrorKind::kParse, field_path("word_start"), "not a boolean");
        phoneme.word_start = it->get<bool>();
      }
      if (!line.phonemes.empty() && phoneme.start < line.phonemes.back().start) {
        Fail(IoErrorKind::kParse, field_path("start"),
             "start goes backwards (" + std::to_string(phoneme.start.count()) + " s after " +
                 std::to_string(line.phonemes.back().start.count()) + " s)");
      }
      if ((phoneme.start + phoneme.duration).count() > kPhonemeTrackMaxSeconds) {
        Fail(IoErrorKind::kAbsurdCount, field_path("duration"), "phoneme ends after 24 hours");
      }
      line.phonemes.push_back(phoneme);
    }
    return track;
  }

 private:
  std::string_view text_;
  const std::string& path_;
};

void AppendNumber(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

}  // namespace

PhonemeTrack ParsePhonemeTrack(std::string_view json, const std::string& path) {
  if (json.size() > kPhonemeTrackMaxFileBytes) {
    throw IoError(IoErrorKind::kAbsurdCount, path,
                  std::to_string(json.size()) + " bytes (at most " +
                      std::to_string(kPhonemeTrackMaxFileBytes) + ")");
  }
  CheckJsonNesting(json, path);
  return TrackReader(json, path).Read();
}

PhonemeTrack ReadPhonemeTrack(const std::filesystem::path& path) {
  const std::string text = ReadInputText(path, kPhonemeTrackMaxFileBytes);
  return ParsePhonemeTrack(text, path.string());
}

std::string FormatPhonemeTrack(const SpeechLine& line, std::string_view audio_path) {
  // One phoneme per line, so that reader errors point at a useful line.
  std::string out = "{\n  \"format\": \"";
  out += kFormatName;
  out += "\",\n  \"version\": " + std::to_string(kPhonemeTrackVersion) + ",\n";
  out += "  \"text\": " + Json(line.text).dump(-1, ' ', false, Json::error_handler_t::replace);
  out += ",\n  \"language\": " + Json(std::string(line.language.view())).dump() + ",\n";
  if (!audio_path.empty()) {
    out += "  \"audio\": " +
           Json(std::string(audio_path)).dump(-1, ' ', false, Json::error_handler_t::replace) +
           ",\n";
  }
  out += "  \"phonemes\": [";
  for (std::size_t i = 0; i < line.phonemes.size(); ++i) {
    const Phoneme& p = line.phonemes[i];
    out += i == 0 ? "\n    {\"start\": " : ",\n    {\"start\": ";
    AppendNumber(out, p.start.count());
    out += ", \"duration\": ";
    AppendNumber(out, p.duration.count());
    out += ", \"symbol\": " +
           Json(std::string(p.symbol.view())).dump(-1, ' ', false, Json::error_handler_t::replace);
    if (p.word_start) out += ", \"word_start\": true";
    if (!p.language.empty() && !(p.language == line.language)) {
      out += ", \"language\": " + Json(std::string(p.language.view())).dump();
    }
    out += "}";
  }
  out += line.phonemes.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

void WritePhonemeTrack(const std::filesystem::path& path, const SpeechLine& line,
                       std::string_view audio_path) {
  // Refuse what the reader would refuse, before touching the file.
  Seconds previous(0.0);
  for (std::size_t i = 0; i < line.phonemes.size(); ++i) {
    const Phoneme& p = line.phonemes[i];
    const std::string where = "phoneme " + std::to_string(i) + ": ";
    if (!std::isfinite(p.start.count()) || !std::isfinite(p.duration.count()) || p.start.count() < 0.0 ||
        p.duration.count() < 0.0) {
      throw IoError(IoErrorKind::kNonFinite, path.string(),
                    where + "start and duration must be finite and >= 0");
    }
    if (p.start < previous) {
      throw IoError(IoErrorKind::kParse, path.string(), where + "start goes backwards");
    }
    if (p.symbol.empty()) throw IoError(IoErrorKind::kParse, path.string(), where + "empty symbol");
    previous = p.start;
  }
  WriteFileAtomically(path, FormatPhonemeTrack(line, audio_path));
}

}  // namespace facerig
