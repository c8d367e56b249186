// A talking character: phonemes -> coarticulated visemes -> rig weights, with
// emotions layered on speech, then blinks and idle gaze (saccades) through the
// weight channels (weight_channels.h), driven by an animation clock (the audio
// playback position; see audio_clock.h).
//
// CharacterRig holds what is built once per rig (viseme and emotion mappings,
// blink shapes); many Characters may share one. A Character is the
// per-character context: every buffer is sized in its constructor, and
// Speak() and Update() allocate nothing, throw nothing
// and take no lock (a test counts operator new). Results are deterministic
// for a given phoneme track, sequence of times and seed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/behaviour/emotion.h"
#include "facerig/runtime/behaviour/gaze.h"
#include "facerig/runtime/behaviour/weight_channels.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/speech/coarticulation.h"
#include "facerig/runtime/speech/phoneme.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "facerig/runtime/speech/viseme.h"
#include "facerig/runtime/speech/viseme_mapping.h"
#include "facerig/runtime/speech/viseme_track.h"

namespace facerig {

struct CharacterRigOptions {
  VisemeMappingOptions visemes;
  const EmotionOverrides* emotions = nullptr;  // optional user recipes
};

// Immutable per-rig data shared by all characters on that rig.
class CharacterRig {
 public:
  // Never throws for a rig that lacks shapes: speech, emotions or blinks that
  // cannot be shown are left out and reported in warnings(). `rig` must
  // outlive the CharacterRig.
  static CharacterRig Build(const Rig& rig, const CharacterRigOptions& options = {});

  const Rig& rig() const { return *rig_; }
  const VisemeMapping& visemes() const { return visemes_; }
  const EmotionRig& emotions() const { return emotions_; }
  // eyeBlink_L / eyeBlink_R shape indices, when the rig has them.
  std::optional<std::size_t> blink_left() const { return blink_left_; }
  std::optional<std::size_t> blink_right() const { return blink_right_; }
  // eyeLook* shape indices in GazeShape order, when the rig has all eight.
  const std::optional<std::array<std::uint32_t, kGazeShapeCount>>& gaze_shapes() const { return gaze_shapes_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  const Rig* rig_ = nullptr;
  VisemeMapping visemes_;
  EmotionRig emotions_;
  std::optional<std::size_t> blink_left_, blink_right_;
  std::optional<std::array<std::uint32_t, kGazeShapeCount>> gaze_shapes_;
  std::vector<std::string> warnings_;
};

struct CharacterParams {
  CoarticulationParams coarticulation;
  VisemeTimingParams timing;
  BlinkParams blink;
  GazeParams gaze;
  float jaw_intensity = 1.0f;  // JALI jaw, [0, 4]
  float lip_intensity = 1.0f;  // JALI lip, [0, 4]
  std::uint64_t seed = 0;      // blinks and gaze
  // Viseme keys held at once: a line of up to (key_capacity / 2 - 1)
  // phonemes. A key is ~24 bytes; 8192 covers about 4000 phonemes (several
  // minutes of speech).
  std::size_t key_capacity = 8192;
  // A silence between keys longer than this is a pause (blinks favour pauses).
  double pause_gap = 0.12;
  // Output weights below this are set to 0, so the blend skips shapes whose
  // effect is invisible (dominance tails leave many tiny weights; on the
  // default head this drops ~20% of the blend work during speech).
  float weight_epsilon = 1e-3f;
};

enum class CharacterError : std::uint8_t {
  kNone,
  kNonFiniteTime,
  kInvalidPhoneme,  // non-finite or negative start/duration, or starts going backwards
  kTooManyKeys,     // the line needs more than key_capacity keys; nothing changed
  kInvalidKey,      // the timing params made an invalid viseme key; the line was dropped
  kNoOpenLine,      // PushPhoneme or EndLine without BeginLine
};

const char* ToString(CharacterError error);

class Character {
 public:
  explicit Character(const CharacterRig& rig, const CharacterParams& params = {});
  Character(const Character&) = delete;
  Character& operator=(const Character&) = delete;

  // Schedule-ahead mode: replaces what is being said by a whole line whose
  // time 0 is `start_time` on the animation clock. On error nothing
  // changes. Call from the thread that calls Update().
  CharacterError Speak(std::span<const Phoneme> phonemes, Seconds start_time);

  // Streaming mode, for phonemes that arrive while the line plays (a TTS
  // engine's or an aligner's events): BeginLine starts a new, empty line at
  // `start_time` on the animation clock (replacing what is being said),
  // PushPhoneme appends the next phoneme (times from the line's start, starts
  // never going backwards), EndLine says no more will come. A phoneme shows
  // once the next one (or EndLine) gives its end, so a source should push
  // each as soon as it is known. On error nothing changes, except
  // kInvalidKey, which drops the line as Speak does. Allocates nothing;
  // call from the thread that calls Update().
  CharacterError BeginLine(Seconds start_time);
  CharacterError PushPhoneme(const Phoneme& phoneme);
  CharacterError EndLine();

  // Stops speaking at once (the mouth relaxes over the next frames).
  void StopSpeaking();

  // Blinks and idle gaze on or off (both on by default); when off, the
  // lids stay open and the eyes look ahead.
  void SetBlinking(bool enabled) { blinking_ = enabled; }
  void SetGazing(bool enabled) { params_.gaze.enabled = enabled; }

  // Emotion target in [0,1] (clamped); reached with the emotion's attack or
  // release time. Several may be active.
  void SetEmotion(Emotion emotion, float target);
  EmotionState& emotion_state() { return emotion_state_; }

  // Per frame: computes the rig weights at animation time `time`.
  // Times may go backwards (a seek or restart): speech follows the time,
  // blinks restart their clock. A non-finite time is refused and the previous
  // weights are kept.
  CharacterError Update(Seconds time);

  // The rig weights of the last Update, one per rig shape, in [0,1].
  std::span<const float> weights() const { return weights_; }
  const VisemeWeights& viseme_weights() const { return viseme_weights_; }
  // The viseme with the largest weight (kSil when the mouth rests).
  Viseme dominant_viseme() const;
  // The phoneme under the clock at the last Update, if any.
  const Phoneme* current_phoneme() const { return current_phoneme_; }
  // True between the first and last key of the current line (with the
  // coarticulation window).
  bool talking() const { return talking_; }
  bool at_pause() const { return at_pause_; }
  float blink_left() const { return blink_left_; }
  float blink_right() const { return blink_right_; }
  // Where the eyes look (GazeJob), also when the rig has no eyeLook* shapes.
  Gaze gaze() const { return gaze_state_.gaze(); }
  // Keys of the current line (line time), for tools and tests.
  std::span<const VisemeKey> keys() const { return track_.keys(); }

 private:
  VisemeTrackError AppendPhoneme(const Phoneme& phoneme);
  VisemeTrackError FinishKeys();
  void ClearLine();
  void UpdateTalkingState(Seconds line_time);
  // The behaviours' weight channels at `time`, then speech + channels -> weights_.
  void UpdateBehaviours(Seconds time);
  void CombineWeights();

  const CharacterRig* rig_;
  CharacterParams params_;

  // Current line, in line time (0 = its start on the animation clock).
  Seconds line_start_{0.0};
  VisemeTrack track_;                  // capacity params_.key_capacity
  std::vector<Phoneme> phonemes_;      // same capacity, for current_phoneme()
  std::size_t phoneme_count_ = 0;
  VisemeKeyStream key_stream_;
  bool line_open_ = false;  // between BeginLine and EndLine
  bool blinking_ = true;

  // Per-frame state and outputs.
  bool has_time_ = false;
  Seconds last_time_{0.0};
  EmotionState emotion_state_;
  BlinkState blink_state_;
  GazeState gaze_state_;
  // Weight channels, sized once: emotions (one per contribution), blinks
  // (eyeBlink_L, eyeBlink_R), gaze (eyeLook*); the counts in use this frame.
  std::vector<ChannelValue> emotion_values_;
  std::array<ChannelValue, 2> blink_values_{};
  std::array<ChannelValue, kGazeShapeCount> gaze_values_{};
  std::size_t emotion_value_count_ = 0, blink_value_count_ = 0, gaze_value_count_ = 0;
  VisemeWeights viseme_weights_{};
  std::vector<float> speech_weights_;
  std::vector<float> weights_;
  const Phoneme* current_phoneme_ = nullptr;
  bool talking_ = false;
  bool at_pause_ = false;
  float blink_left_ = 0.0f;
  float blink_right_ = 0.0f;
};

}  // namespace facerig
