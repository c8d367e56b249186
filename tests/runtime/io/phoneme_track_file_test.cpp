#include "facerig/runtime/io/phoneme_track_file.h"

#include <filesystem>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

using Catch::Matchers::Contains;

SpeechLine SampleLine() {
  SpeechLine line;
  line.text = "A pit, \"quoted\" \xC3\xA9t\xC3\xA9";
  line.language.assign("en-us");
  auto add = [&](double start, double duration, std::string_view symbol, bool word,
                 std::string_view language = "en-us") {
    line.phonemes.push_back(facerig::test::MakePhoneme(start, duration, symbol, language, word));
  };
  add(0.0, 0.061, "a#", true);
  add(0.110430839, 0.0326530612, "p", true);
  add(0.143, 0.197, "I", false);
  add(0.34, 0.0, "t", false);
  add(0.34, 0.3, "aI@", false, "en");  // a language switch inside the line
  add(0.64, 0.0, "_:", false);
  return line;
}

// Expects ParsePhonemeTrack(text) to throw IoError of `kind` whose message
// contains `pointer` and whose line is `line` (0: do not check).
void ExpectError(const std::string& text, IoErrorKind kind, const std::string& pointer,
                 std::int64_t line = 0) {
  INFO(text);
  try {
    ParsePhonemeTrack(text, "track.json");
    FAIL("no error");
  } catch (const IoError& e) {
    INFO(e.what());
    CHECK(e.kind() == kind);
    CHECK(e.path() == "track.json");
    CHECK_THAT(e.message(), Contains(pointer));
    if (line > 0) CHECK(e.line() == line);
  }
}

std::string Track(const std::string& phonemes) {
  return "{\n\"version\": 1,\n\"language\": \"en\",\n\"phonemes\": [\n" + phonemes + "\n]\n}\n";
}

TEST_CASE("Phoneme track: write then read gives the same line", "[speech][track]") {
  const SpeechLine line = SampleLine();
  const auto path = test::OutputPath("track_roundtrip.json");
  WritePhonemeTrack(path, line, "audio/a pit.wav");
  const PhonemeTrack track = ReadPhonemeTrack(path);
  CHECK(track.audio_path == "audio/a pit.wav");
  CHECK(track.line.text == line.text);
  CHECK(track.line.language == line.language);
  CHECK(track.line.sample_rate == 0);
  CHECK(track.line.audio.empty());
  REQUIRE(track.line.phonemes.size() == line.phonemes.size());
  for (std::size_t i = 0; i < line.phonemes.size(); ++i) {
    INFO(i);
    const Phoneme& a = line.phonemes[i];
    const Phoneme& b = track.line.phonemes[i];
    CHECK(a.start.count() == b.start.count());  // shortest round-trip formatting: exact
    CHECK(a.duration.count() == b.duration.count());
    CHECK(a.symbol == b.symbol);
    CHECK(a.language == b.language);
    CHECK(a.word_start == b.word_start);
  }
  // No audio path, empty track.
  SpeechLine empty;
  empty.language.assign("fr");
  WritePhonemeTrack(path, empty);
  const PhonemeTrack read = ReadPhonemeTrack(path);
  CHECK(read.audio_path.empty());
  CHECK(read.line.phonemes.empty());
  CHECK(read.line.language.view() == "fr");
}

TEST_CASE("Phoneme track: minimal file, optional fields", "[speech][track]") {
  const PhonemeTrack track =
      ParsePhonemeTrack(Track(R"({"start": 0, "duration": 0.1, "symbol": "h"},
{"start": 0.1, "duration": 0, "symbol": "@U", "word_start": false, "language": "en-gb"})"));
  CHECK(track.line.text.empty());
  REQUIRE(track.line.phonemes.size() == 2);
  CHECK(track.line.phonemes[0].language.view() == "en");
  CHECK(track.line.phonemes[1].language.view() == "en-gb");
  CHECK(track.line.phonemes[1].duration.count() == 0.0);
}

TEST_CASE("Phoneme track: errors name the file, JSON path and line", "[speech][track]") {
  // Malformed JSON: line of the syntax error.
  ExpectError("{\n\"version\": 1,\n\"language\": \"en\",\n\"phonemes\": [ {\"start\": 0,, } ]\n}",
              IoErrorKind::kParse, "malformed JSON", 4);
  ExpectError("", IoErrorKind::kParse, "malformed JSON");
  ExpectError("[1, 2]", IoErrorKind::kParse, "not a JSON object");
  // Missing fields.
  ExpectError(R"({"language": "en", "phonemes": []})", IoErrorKind::kParse, "missing \"version\"");
  ExpectError(R"({"version": 1, "phonemes": []})", IoErrorKind::kParse, "missing \"language\"");
  ExpectError(R"({"version": 1, "language": "en"})", IoErrorKind::kParse, "missing \"phonemes\"");
  ExpectError(Track(R"({"start": 0, "duration": 0.1, "symbol": "a"},
{"start": 0.1, "symbol": "b"})"),
              IoErrorKind::kParse, "/phonemes/1: missing \"duration\"", 6);
  // Wrong types.
  ExpectError(Track(R"({"start": "0", "duration": 0.1, "symbol": "a"})"), IoErrorKind::kParse,
              "/phonemes/0/start", 5);
  ExpectError(Track(R"({"start": 0, "duration": 0.1, "symbol": 7})"), IoErrorKind::kParse,
              "/phonemes/0/symbol");
  ExpectError(Track(R"({"start": 0, "duration": 0.1, "symbol": "a", "word_start": 1})"),
              IoErrorKind::kParse, "/phonemes/0/word_start");
  ExpectError(R"({"version": 1, "language": "en", "phonemes": {}})", IoErrorKind::kParse,
              "/phonemes: not an array");
  // Bad times.
  ExpectError(Track(R"({"start": -0.5, "duration": 0.1, "symbol": "a"})"), IoErrorKind::kNonFinite,
              "/phonemes/0/start: start is negative");
  ExpectError(Track(R"({"start": 0, "duration": -1, "symbol": "a"})"), IoErrorKind::kNonFinite,
              "/phonemes/0/duration");
  ExpectError(Track(R"({"start": NaN, "duration": 0.1, "symbol": "a"})"), IoErrorKind::kParse,
              "malformed JSON");
  ExpectError(Track(R"({"start": 1e999, "duration": 0.1, "symbol": "a"})"),
              IoErrorKind::kNonFinite, "");
  ExpectError(Track(R"({"start": 0.5, "duration": 0.1, "symbol": "a"},
{"start": 0.2, "duration": 0.1, "symbol": "b"})"),
              IoErrorKind::kParse, "/phonemes/1/start: start goes backwards", 6);
  ExpectError(Track(R"({"start": 1e9, "duration": 0.1, "symbol": "a"})"),
              IoErrorKind::kAbsurdCount, "/phonemes/0/start");
  // Symbols: at most 8 bytes, not empty.
  ExpectError(Track(R"({"start": 0, "duration": 0.1, "symbol": "abcdefghi"})"),
              IoErrorKind::kParse, "/phonemes/0/symbol: symbol is 9 bytes long");
  ExpectError(Track(R"({"start": 0, "duration": 0.1, "symbol": ""})"), IoErrorKind::kParse,
              "symbol is empty");
  ExpectError(R"({"version": 1, "language": "a-very-long-language-name", "phonemes": []})",
              IoErrorKind::kParse, "/language");
  // Versions and format.
  ExpectError(R"({"version": 2, "language": "en", "phonemes": []})",
              IoErrorKind::kUnsupportedVersion, "version 2");
  ExpectError(R"({"format": "other", "version": 1, "language": "en", "phonemes": []})",
              IoErrorKind::kBadMagic, "/format");
  // Absurd size.
  const std::string huge(kPhonemeTrackMaxFileBytes + 1, ' ');
  ExpectError(huge, IoErrorKind::kAbsurdCount, "bytes");
}

TEST_CASE("Phoneme track: missing file and refused writes", "[speech][track]") {
  CHECK_THROWS_AS(ReadPhonemeTrack(test::OutputPath("no_such_track.json")), IoError);
  const auto path = test::OutputPath("track_refused.json");
  WritePhonemeTrack(path, SampleLine());
  SpeechLine bad = SampleLine();
  bad.phonemes[2].start = facerig::Seconds(std::numeric_limits<double>::quiet_NaN());
  CHECK_THROWS_AS(WritePhonemeTrack(path, bad), IoError);
  bad = SampleLine();
  bad.phonemes[2].start = facerig::Seconds(0.01);  // backwards
  CHECK_THROWS_AS(WritePhonemeTrack(path, bad), IoError);
  // The earlier file is untouched.
  CHECK(ReadPhonemeTrack(path).line.phonemes.size() == SampleLine().phonemes.size());
}

}  // namespace
}  // namespace facerig
