// Phoneme -> viseme: the espeak-ng phoneme table (names as espeak-ng reports
// them in phoneme events, Kirshenbaum-style ASCII, e.g. "aI", "tS", "@L") and
// the timing corrections that turn a phoneme track into viseme keys.
//
// Pure runtime-core code: no espeak-ng dependency. Tables cover the voices
// en-us, en, pt-br, pt, es, fr, de, it, fi, nl, pl, ru, hi and cmn; any other
// language uses the shared base table.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"
#include "facerig/runtime/speech/viseme.h"

namespace facerig {

// What one phoneme looks like on the lips.
struct PhonemeVisemes {
  // Articulation class, used by the timing corrections.
  enum Flags : std::uint8_t {
    kNone = 0,
    kVowel = 1 << 0,          // vowels and diphthongs
    kUnvoicedStop = 1 << 1,   // p t k tS (and aspirated/affricate kin): closure before the event
    kLagSource = 1 << 2,      // l r n m w j: a following vowel is reported late
  };

  std::array<Viseme, 2> visemes{Viseme::kSil, Viseme::kSil};
  // 0: no articulation of its own (stress, tone, language switch, glottal
  // stop): produces no key; the previous key holds through it.
  // 1: one viseme. 2: a diphthong (or affricate) split over two visemes.
  std::uint8_t count = 1;
  // Share of the phoneme's duration given to visemes[0] when count == 2, in (0,1).
  float split = 0.5f;
  // Articulation strength in [0,1]: lower for reduced vowels (schwa) and h.
  float strength = 1.0f;
  std::uint8_t flags = kNone;

  bool has(Flags flag) const { return (flags & flag) != 0; }
};

// Looks up an espeak-ng phoneme symbol for a language ("en-us", "pt-br",
// "cmn", ...). Tries the language's own table ("en-us"), then its primary
// subtag ("en"), then the shared base table. Stress marks (' , % =) are
// stripped; a symbol not found is retried without its length mark (':') and
// then without trailing variant marks (# ; . ~ - / " and digits, e.g. "t#",
// "I2", "n^" -> "n"). Pauses ("_", "_:", "_!", "_|", "||", ...) map to sil;
// language switches ("(en)"), stress-only, tone ("55", "214") and virtual
// ("#X1") symbols map to count == 0. Returns nullopt for unknown symbols.
std::optional<PhonemeVisemes> LookupPhonemeVisemes(std::string_view language,
                                                   std::string_view symbol);

// A symbol of a track that has no mapping (falls back to
// VisemeTimingParams::unmapped_viseme at runtime).
struct UnmappedSymbol {
  std::string language;
  std::string symbol;
  std::size_t count = 0;  // occurrences in the track
};

// Every distinct (language, symbol) of `phonemes` without a mapping, in order
// of first occurrence. Empty when the whole track is mapped.
std::vector<UnmappedSymbol> FindUnmappedSymbols(std::span<const Phoneme> phonemes);

// Timing corrections for espeak-ng-style phoneme events (espeak-ng marks a
// stop's release and reports some vowels late). All times in seconds.
struct VisemeTimingParams {
  // Unvoiced stops (p t k tS): the event marks the release; the closure is
  // 40-50 ms of silence before it, so their key starts this much earlier.
  double stop_closure = 0.045;
  // Vowels after l r n m w j are reported 30-60 ms late: their key starts
  // this much earlier.
  double vowel_lag = 0.040;
  // Zero-length (and very short) events last at least this long, without
  // overlapping the next key; an earlier shift never shortens the previous
  // key below this either (unless it was shorter to begin with).
  double min_duration = 0.030;
  // Used for symbols without a mapping: a neutral, half-open mouth.
  Viseme unmapped_viseme = Viseme::kE;
  float unmapped_strength = 0.5f;
};

// At most this many keys per phoneme (a diphthong gives two).
inline constexpr std::size_t kMaxVisemeKeysPerPhoneme = 2;

// Streaming phoneme -> viseme keys, allocation-free and exception-free.
// Keys are written one phoneme behind: a phoneme's keys are final only once
// its successor is known (the successor may start earlier than reported and
// so end the phoneme's key early). Keys come out in time order, each
// [start, end] with end >= start and never overlapping the next.
//
// Bad times are repaired rather than refused: a non-finite or negative start
// is taken as the previous phoneme's start (or 0), a start before the
// previous one is clamped to it, a non-finite or negative duration counts as 0.
class VisemeKeyStream {
 public:
  explicit VisemeKeyStream(const VisemeTimingParams& params = {}) : params_(params) {}

  // Feeds the next phoneme (in time order) and writes the keys of the
  // previous one into `out`. Returns how many were written (0..2), or nullopt
  // when `out` may be too small (size < kMaxVisemeKeysPerPhoneme); nothing is
  // consumed then, so the call can be repeated with a larger span.
  std::optional<std::size_t> Push(const Phoneme& phoneme, std::span<VisemeKey> out);
  // Writes the keys of the last phoneme (end of the line). Same return rules.
  std::optional<std::size_t> Finish(std::span<VisemeKey> out);
  // Forgets the pending phoneme, for a new line.
  void Reset();

  const VisemeTimingParams& params() const { return params_; }

 private:
  std::size_t EmitPending(double end, std::span<VisemeKey> out);

  VisemeTimingParams params_;
  bool has_pending_ = false;
  PhonemeVisemes pending_map_{};
  double pending_start_ = 0.0;      // corrected key start
  double pending_reported_ = 0.0;   // start as reported by the source
  double pending_end_ = 0.0;        // reported end (start + duration, min_duration applied)
  double last_reported_start_ = 0.0;
};

// The whole track: PhonemesToVisemeKeys(line.phonemes, params). Same result as
// feeding every phoneme to a VisemeKeyStream, then Finish().
std::vector<VisemeKey> PhonemesToVisemeKeys(std::span<const Phoneme> phonemes,
                                            const VisemeTimingParams& params = {});

}  // namespace facerig
