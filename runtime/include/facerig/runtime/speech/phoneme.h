// Timed phonemes: what every phoneme source (espeak-ng, a phoneme-track file,
// another TTS engine's timestamps) produces and the viseme stage consumes.
// Times are seconds from the start of the line's audio.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/seconds.h"

namespace facerig {

// A short, fixed-size, zero-terminated name: phoneme symbols are at most 8
// bytes in espeak-ng; voices/languages like "en-us" or "pt-br" fit easily.
// Fixed size so phonemes can be queued and copied without allocation.
template <std::size_t N>
struct ShortName {
  std::array<char, N + 1> bytes{};

  ShortName() = default;
  // Truncates to N bytes.
  explicit ShortName(std::string_view text) { assign(text); }
  void assign(std::string_view text) {
    const std::size_t n = text.size() < N ? text.size() : N;
    for (std::size_t i = 0; i < n; ++i) bytes[i] = text[i];
    for (std::size_t i = n; i <= N; ++i) bytes[i] = '\0';
  }
  std::string_view view() const { return std::string_view(bytes.data()); }
  bool empty() const { return bytes[0] == '\0'; }
  friend bool operator==(const ShortName& a, const ShortName& b) { return a.view() == b.view(); }
};

using PhonemeSymbol = ShortName<8>;
using LanguageName = ShortName<15>;

struct Phoneme {
  Seconds start{0.0};     // from the start of the line's audio
  Seconds duration{0.0};  // may be 0 (espeak-ng reports some events with no length)
  PhonemeSymbol symbol;   // the source's own name, e.g. espeak-ng "aI", "p", "_:" (pause)
  LanguageName language;  // voice / language the symbol belongs to, e.g. "en-us"
  bool word_start = false;
};

// A whole line: its phonemes in time order and, when synthesized, its audio.
struct SpeechLine {
  std::string text;
  LanguageName language;
  int sample_rate = 0;                 // Hz; 0 when there is no audio
  std::vector<std::int16_t> audio;     // mono
  std::vector<Phoneme> phonemes;

  Seconds audio_duration() const { return SamplesToSeconds(audio.size(), sample_rate); }
};

}  // namespace facerig
