// Phoneme-track files (JSON): pre-baked lines, or another TTS engine's
// timestamps. Holds a line's text, language and timed phonemes; no audio, but
// optionally the path of an audio file that goes with it.
//
//   {
//     "format": "facerig-phoneme-track", "version": 1,
//     "text": "a pit", "language": "en-us",
//     "audio": "a_pit.wav",                                  (optional)
//     "phonemes": [
//       {"start": 0.0, "duration": 0.06, "symbol": "a#", "word_start": true},
//       {"start": 0.11, "duration": 0.03, "symbol": "p", "word_start": true,
//        "language": "en"},                                  (optional; default: the line's)
//       ...
//     ]
//   }
//
// Times in seconds from the start of the line's audio: finite, >= 0, starts
// never decreasing. "format" is optional on reading; "version" is required.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

inline constexpr int kPhonemeTrackVersion = 1;
// Limits beyond which a file is refused as absurd (IoErrorKind::kAbsurdCount).
inline constexpr std::size_t kPhonemeTrackMaxFileBytes = std::size_t{64} << 20;
inline constexpr std::size_t kPhonemeTrackMaxPhonemes = 1'000'000;
inline constexpr std::size_t kPhonemeTrackMaxTextBytes = std::size_t{1} << 20;
inline constexpr double kPhonemeTrackMaxSeconds = 24.0 * 3600.0;

struct PhonemeTrack {
  SpeechLine line;         // sample_rate 0 and no audio
  std::string audio_path;  // as written in the file (relative to it, usually); empty if none
};

// Reads a track file. Throws IoError with the path, the JSON pointer of the
// offending value (e.g. "/phonemes/3/start") in the message and its line:
// kOpenFailed (also for a FIFO, device or directory), kParse (malformed JSON,
// JSON nested deeper than kMaxJsonNesting, missing or mistyped fields, symbols
// longer than 8 bytes, backwards starts), kNonFinite (NaN/Inf, negative or
// overflowing times), kAbsurdCount (sizes over the limits above),
// kUnsupportedVersion.
PhonemeTrack ReadPhonemeTrack(const std::filesystem::path& path);
// Same, from text; `path` is only used in error messages.
PhonemeTrack ParsePhonemeTrack(std::string_view json, const std::string& path = "<memory>");

// Writes `line` (text, language, phonemes; not its audio) atomically. Throws
// IoError: kWriteFailed; for a line the reader would refuse, before writing
// anything, kNonFinite (NaN/Inf/negative times) or kParse (backwards starts,
// empty symbols). Text that is not valid UTF-8 is written with U+FFFD.
void WritePhonemeTrack(const std::filesystem::path& path, const SpeechLine& line,
                       std::string_view audio_path = {});
std::string FormatPhonemeTrack(const SpeechLine& line, std::string_view audio_path = {});

}  // namespace facerig
