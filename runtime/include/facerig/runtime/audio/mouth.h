// The rough mode: a coarse mouth track from audio alone, for recordings
// without a transcript. Loudness says open or closed; the spectral shape
// picks one of a few classes: open vowel, front vowel, rounded vowel,
// fricative. It does not recognise phonemes, and it shows:
// - the lips close only where the sound stops: a silent stop closure (p, t, k
//   alike) closes them, a voiced m or b keeps them open;
// - nasals and r count as rounded or front vowels, mid vowels (o in "go")
//   as open ones;
// - class boundaries follow the acoustics, not the lips, which lead the sound;
// - at 8 kHz (telephone audio) the frication band (4-8 kHz) is gone: no fricatives.
// The thresholds were set on espeak-ng speech (tests/espeak/audio_mouth_espeak_test.cpp
// measures them). Use a transcript-aligned track whenever there is a transcript.
//
// A pure chain over a whole buffer (offline, not per-frame code):
//   AnalyzeMouthFrames (audio_mouth_features.h) -> ClassifyMouthFrames
//   -> MouthShapesToPhonemes, or all three in RoughMouthFromAudio;
// RoughMouthStream (audio_mouth_stream.h) does the same for audio in chunks.
// The result is an ordinary phoneme track: each shape becomes one phoneme
// symbol that the phoneme -> viseme tables map in every language (see
// RoughMouthSymbol), so it goes through coarticulation like any other track.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "facerig/runtime/audio/mouth_features.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

enum class MouthShape : std::uint8_t {
  kRest,       // silence: mouth at rest ("_", viseme sil)
  kClosed,     // a short gap inside speech: lips closed ("b", viseme PP)
  kOpen,       // open vowel ("a", viseme aa)
  kFront,      // front vowel ("i", viseme ih)
  kRounded,    // rounded or back vowel, also nasals ("o", viseme oh)
  kFricative,  // strong high-frequency noise ("s", viseme SS)
};

// The phoneme symbol a shape is written as: "_", "b", "a", "i", "o", "s".
std::string_view RoughMouthSymbol(MouthShape shape);

// Thresholds in dB (differences of MouthFrameFeatures levels), times in seconds.
struct AudioMouthParams {
  MouthAnalysisParams analysis;
  // Features are median-filtered over this many frames (odd, 1 = off) before
  // classification.
  int median_frames = 5;

  // Voice activity on the smoothed frame levels. A frame turns voiced above
  // the "on" threshold and back to silence below on - hysteresis_db, where
  //   on = clamp(floor + above_floor_db, loud - max_below_loud_db, loud - min_below_loud_db)
  // but never below floor + min_above_floor_db (noise alone stays silent) nor
  // min_voice_db. Whole buffer: the floor is the 2nd percentile of the
  // levels, the loud level the 95th. Streaming: the floor follows the level
  // down at once and rises by floor_rise_db_per_second; the loud level
  // follows it up at once and falls by loud_fall_db_per_second.
  float above_floor_db = 12.0f;
  float min_above_floor_db = 6.0f;
  float min_below_loud_db = 15.0f;
  float max_below_loud_db = 30.0f;
  float hysteresis_db = 4.0f;
  float min_voice_db = -60.0f;
  float floor_rise_db_per_second = 2.0f;
  float loud_fall_db_per_second = 2.0f;

  // Classes of voiced frames, tried in this order:
  // fricative: frication band minus the strongest formant band > fricative_db;
  // front: front-formant band minus back-formant band > front_over_back_db and
  //   minus high-formant band > front_over_high_db (a weak back band alone is a u);
  // open: high-formant band minus low-formant band > open_db; else rounded.
  float fricative_db = 0.0f;
  float front_over_back_db = 8.0f;
  float front_over_high_db = -3.0f;
  float open_db = -8.0f;

  // Shorter segments are merged into their longer neighbour.
  double min_segment = 0.050;
  // A silence between sounds shorter than this closes the lips (kClosed);
  // longer ones, and silence at either end, rest (kRest).
  double max_closure = 0.150;
  // The language the symbols are tagged with; empty: none (the shared table).
  LanguageName language;
};

// One shape per frame (kRest for every silent frame; kClosed is decided on
// segments, by MouthShapesToPhonemes). Empty for empty input.
std::vector<MouthShape> ClassifyMouthFrames(std::span<const MouthFrameFeatures> frames,
                                            const AudioMouthParams& params = {});

// Frame shapes (frame i centred on i * hop_seconds) -> phonemes covering
// [0, duration] without gaps: runs of equal shapes, runs shorter than
// params.min_segment merged into their longer neighbour, silent runs split
// into kClosed and kRest by length. Empty for empty input or a hop that is
// not finite and positive.
std::vector<Phoneme> MouthShapesToPhonemes(std::span<const MouthShape> shapes,
                                           double hop_seconds, double duration,
                                           const AudioMouthParams& params = {});

// The whole rough mode: a line with the phonemes (text empty, no audio,
// language params.language). nullopt when the sample rate is outside
// [kMouthMinSampleRate, kMouthMaxSampleRate] or the analysis params are bad;
// no phonemes for no samples. Samples as in AnalyzeMouthFrames.
std::optional<SpeechLine> RoughMouthFromAudio(std::span<const float> samples, int sample_rate,
                                              const AudioMouthParams& params = {});
std::optional<SpeechLine> RoughMouthFromAudio(std::span<const std::int16_t> samples,
                                              int sample_rate,
                                              const AudioMouthParams& params = {});

}  // namespace facerig
