#include "facerig/runtime/character.h"

#include <algorithm>
#include <cmath>

namespace facerig {
namespace {

std::optional<std::size_t> FirstShape(const Rig& rig, std::string_view name) {
  const std::vector<std::size_t> found = FindShapesByArkitName(rig, name);
  if (found.empty()) return std::nullopt;
  return found.front();
}

bool ValidPhoneme(const Phoneme& phoneme) {
  return std::isfinite(phoneme.start.count()) && std::isfinite(phoneme.duration.count()) &&
         phoneme.start >= Seconds(0.0) && phoneme.duration >= Seconds(0.0);
}

}  // namespace

const char* ToString(CharacterError error) {
  switch (error) {
    case CharacterError::kNone: return "no error";
    case CharacterError::kNonFiniteTime: return "time is NaN or infinite";
    case CharacterError::kInvalidPhoneme: return "phoneme with a non-finite, negative or backwards time";
    case CharacterError::kTooManyKeys: return "line longer than the character's key capacity";
    case CharacterError::kInvalidKey: return "the viseme timing params made an invalid viseme key";
    case CharacterError::kNoOpenLine: return "no line begun: call BeginLine before PushPhoneme or EndLine";
  }
  return "unknown error";
}

CharacterRig CharacterRig::Build(const Rig& rig, const CharacterRigOptions& options) {
  CharacterRig result;
  result.rig_ = &rig;
  VisemeMappingResult visemes = BuildVisemeMapping(rig, options.visemes);
  result.visemes_ = std::move(visemes.mapping);
  result.warnings_ = std::move(visemes.warnings);
  EmotionRigResult emotions = BuildEmotionRig(rig, options.emotions);
  result.emotions_ = std::move(emotions.emotions);
  result.warnings_.insert(result.warnings_.end(), emotions.warnings.begin(), emotions.warnings.end());
  result.blink_left_ = FirstShape(rig, "eyeBlink_L");
  result.blink_right_ = FirstShape(rig, "eyeBlink_R");
  if (!result.blink_left_ || !result.blink_right_) {
    result.warnings_.push_back("no eyeBlink_L / eyeBlink_R shapes: the character will not blink");
  }
  std::array<std::uint32_t, kGazeShapeCount> gaze{};
  bool all_gaze_shapes = true;
  for (std::size_t i = 0; i < kGazeShapeCount; ++i) {
    const std::optional<std::size_t> shape = FirstShape(rig, kGazeShapeNames[i]);
    all_gaze_shapes = all_gaze_shapes && shape.has_value();
    if (shape) gaze[i] = static_cast<std::uint32_t>(*shape);
  }
  if (all_gaze_shapes) {
    result.gaze_shapes_ = gaze;
  } else {
    result.warnings_.push_back("not all eight eyeLook* shapes: the eyes will not move");
  }
  return result;
}

Character::Character(const CharacterRig& rig, const CharacterParams& params)
    : rig_(&rig),
      params_(params),
      track_(std::max<std::size_t>(params.key_capacity, 2 * kMaxVisemeKeysPerPhoneme)),
      phonemes_(std::max<std::size_t>(params.key_capacity, 1)),
      key_stream_(params.timing),
      blink_state_(params.seed),
      gaze_state_(params.seed),
      emotion_values_(rig.emotions().channel_count()),
      speech_weights_(rig.rig().shape_count(), 0.0f),
      weights_(rig.rig().shape_count(), 0.0f) {}

VisemeTrackError Character::AppendPhoneme(const Phoneme& phoneme) {
  if (track_.size() + kMaxVisemeKeysPerPhoneme > track_.capacity() || phoneme_count_ >= phonemes_.size()) {
    return VisemeTrackError::kFull;
  }
  std::array<VisemeKey, kMaxVisemeKeysPerPhoneme> written_keys;
  const std::optional<std::size_t> written = key_stream_.Push(phoneme, written_keys);
  if (!written) return VisemeTrackError::kFull;
  // The only check of these keys: the per-frame coarticulation trusts the track.
  if (const VisemeTrackError error = track_.Append(std::span(written_keys).first(*written));
      error != VisemeTrackError::kNone) {
    return error;
  }
  phonemes_[phoneme_count_++] = phoneme;
  return VisemeTrackError::kNone;
}

VisemeTrackError Character::FinishKeys() {
  std::array<VisemeKey, kMaxVisemeKeysPerPhoneme> written_keys;
  const std::optional<std::size_t> written = key_stream_.Finish(written_keys);
  if (!written) return VisemeTrackError::kFull;
  return track_.Append(std::span(written_keys).first(*written));
}

CharacterError Character::Speak(std::span<const Phoneme> phonemes, Seconds start_time) {
  if (!std::isfinite(start_time.count())) return CharacterError::kNonFiniteTime;
  // Check first so that a refused line changes nothing.
  Seconds previous_start(0.0);
  for (const Phoneme& phoneme : phonemes) {
    if (!ValidPhoneme(phoneme) || phoneme.start < previous_start) return CharacterError::kInvalidPhoneme;
    previous_start = phoneme.start;
  }
  if (phonemes.size() * kMaxVisemeKeysPerPhoneme + kMaxVisemeKeysPerPhoneme > track_.capacity() ||
      phonemes.size() > phonemes_.size()) {
    return CharacterError::kTooManyKeys;
  }
  ClearLine();
  line_start_ = start_time;
  VisemeTrackError error = VisemeTrackError::kNone;
  for (const Phoneme& phoneme : phonemes) {
    if (error == VisemeTrackError::kNone) error = AppendPhoneme(phoneme);
  }
  if (error == VisemeTrackError::kNone) error = FinishKeys();
  if (error != VisemeTrackError::kNone) {
    ClearLine();
    return CharacterError::kInvalidKey;  // capacity was checked above: only a bad key is left
  }
  return CharacterError::kNone;
}

CharacterError Character::BeginLine(Seconds start_time) {
  if (!std::isfinite(start_time.count())) return CharacterError::kNonFiniteTime;
  ClearLine();
  line_start_ = start_time;
  line_open_ = true;
  return CharacterError::kNone;
}

CharacterError Character::PushPhoneme(const Phoneme& phoneme) {
  if (!line_open_) return CharacterError::kNoOpenLine;
  if (!ValidPhoneme(phoneme) || (phoneme_count_ > 0 && phoneme.start < phonemes_[phoneme_count_ - 1].start)) {
    return CharacterError::kInvalidPhoneme;
  }
  // Room for this phoneme's keys and, later, EndLine's.
  if (track_.size() + 2 * kMaxVisemeKeysPerPhoneme > track_.capacity() || phoneme_count_ >= phonemes_.size()) {
    return CharacterError::kTooManyKeys;
  }
  if (AppendPhoneme(phoneme) != VisemeTrackError::kNone) {
    ClearLine();  // capacity was checked above: only a bad key is left, which drops the line as Speak does
    return CharacterError::kInvalidKey;
  }
  return CharacterError::kNone;
}

CharacterError Character::EndLine() {
  if (!line_open_) return CharacterError::kNoOpenLine;
  line_open_ = false;
  if (FinishKeys() != VisemeTrackError::kNone) {
    ClearLine();
    return CharacterError::kInvalidKey;
  }
  return CharacterError::kNone;
}

void Character::ClearLine() {
  line_open_ = false;
  key_stream_.Reset();
  track_.Clear();
  phoneme_count_ = 0;
}

void Character::StopSpeaking() {
  ClearLine();
}

void Character::SetEmotion(Emotion emotion, float target) {
  emotion_state_.SetTarget(emotion, std::clamp(std::isfinite(target) ? target : 0.0f, 0.0f, 1.0f));
}

void Character::UpdateTalkingState(Seconds line_time) {
  const std::span<const VisemeKey> keys = this->keys();
  if (keys.empty()) {
    talking_ = false;
    at_pause_ = false;
    current_phoneme_ = nullptr;
    return;
  }
  talking_ = line_time >= keys.front().start - Seconds(params_.coarticulation.contact_anticipation) &&
             line_time <= keys.back().end + Seconds(params_.coarticulation.contact_release);
  const Seconds pause_gap(params_.pause_gap);
  // The key under the clock: the last one starting at or before line_time.
  const auto after = std::upper_bound(keys.begin(), keys.end(), line_time,
                                      [](Seconds t, const VisemeKey& key) { return t < key.start; });
  at_pause_ = false;
  if (talking_ && after != keys.begin()) {
    const VisemeKey& key = *(after - 1);
    const bool in_gap = line_time > key.end &&
                        after != keys.end() && after->start - key.end > pause_gap;
    at_pause_ = (key.viseme == Viseme::kSil && key.end - key.start > pause_gap &&
                 line_time <= key.end) ||
                in_gap;
  }
  const std::span<const Phoneme> phonemes = std::span(phonemes_).first(phoneme_count_);
  const auto next = std::upper_bound(phonemes.begin(), phonemes.end(), line_time,
                                     [](Seconds t, const Phoneme& p) { return t < p.start; });
  current_phoneme_ = nullptr;
  if (next != phonemes.begin()) {
    const Phoneme& phoneme = *(next - 1);
    if (line_time <= phoneme.start + std::max(phoneme.duration, Seconds(1e-3))) current_phoneme_ = &phoneme;
  }
}

CharacterError Character::Update(Seconds time) {
  if (!std::isfinite(time.count())) return CharacterError::kNonFiniteTime;
  Seconds step{0.0};
  if (has_time_) {
    if (time < last_time_) {
      blink_state_.ForgetTime();  // a seek: blinks restart rather than refuse
    } else {
      step = time - last_time_;
    }
  }
  has_time_ = true;
  last_time_ = time;
  const Seconds line_time = time - line_start_;

  UpdateTalkingState(line_time);

  const CoarticulationJob coarticulation{
      .keys = &track_, .time = line_time, .params = &params_.coarticulation, .out_weights = &viseme_weights_};
  if (coarticulation.Run() != CoarticulationError::kNone) viseme_weights_.fill(0.0f);

  const VisemeWeightsJob to_rig{.mapping = &rig_->visemes(),
                                .viseme_weights = viseme_weights_,
                                .jaw_intensity = params_.jaw_intensity,
                                .lip_intensity = params_.lip_intensity,
                                .out_weights = speech_weights_};
  if (to_rig.Run() != VisemeWeightsJobError::kNone) std::fill(speech_weights_.begin(), speech_weights_.end(), 0.0f);

  emotion_state_.Advance(step);
  UpdateBehaviours(time);
  CombineWeights();
  return CharacterError::kNone;
}

Viseme Character::dominant_viseme() const {
  std::size_t best = 0;
  for (std::size_t v = 1; v < kVisemeCount; ++v) {
    if (viseme_weights_[v] > viseme_weights_[best]) best = v;
  }
  return viseme_weights_[best] > 0.05f ? static_cast<Viseme>(best) : Viseme::kSil;
}

void Character::UpdateBehaviours(Seconds time) {
  const EmotionChannelsJob emotions{.emotions = &rig_->emotions(),
                                    .intensities = emotion_state_.intensity,
                                    .lip_contact = LipContactWeight(viseme_weights_),
                                    .out_values = emotion_values_};
  emotion_value_count_ = emotions.Run() == EmotionChannelsJobError::kNone ? emotion_values_.size() : 0;

  const BlinkJob blink{.params = &params_.blink,
                       .state = &blink_state_,
                       .time = time,
                       .talking = talking_,
                       .at_pause = at_pause_,
                       .out_left = &blink_left_,
                       .out_right = &blink_right_};
  if (!blinking_ || blink.Run() != BlinkError::kNone) blink_left_ = blink_right_ = 0.0f;
  blink_value_count_ = 0;
  if (const auto left = rig_->blink_left()) {
    blink_values_[blink_value_count_++] = {static_cast<std::uint32_t>(*left), blink_left_};
  }
  if (const auto right = rig_->blink_right()) {
    blink_values_[blink_value_count_++] = {static_cast<std::uint32_t>(*right), blink_right_};
  }

  GazeChannels gaze_channels{};
  const GazeJob gaze{.params = &params_.gaze, .state = &gaze_state_, .time = time, .out_channels = &gaze_channels};
  if (gaze.Run() != GazeError::kNone) gaze_channels.fill(0.0f);
  gaze_value_count_ = 0;
  if (const auto& shapes = rig_->gaze_shapes()) {
    for (std::size_t i = 0; i < kGazeShapeCount; ++i) gaze_values_[i] = {(*shapes)[i], gaze_channels[i]};
    gaze_value_count_ = kGazeShapeCount;
  }
}

void Character::CombineWeights() {
  const std::array<ChannelLayer, 3> layers = {{
      {ChannelRule::kAdd, std::span(emotion_values_).first(emotion_value_count_)},
      // Blinks after the emotions: a lid closes fully even when an emotion squints or widens.
      {ChannelRule::kMax, std::span(blink_values_).first(blink_value_count_)},
      // Gaze adds to what the emotions set (e.g. eyeLookDown from sadness).
      {ChannelRule::kAdd, std::span(gaze_values_).first(gaze_value_count_)},
  }};
  const CombineChannelsJob combine{
      .base = speech_weights_, .layers = layers, .zero_below = params_.weight_epsilon, .out_weights = weights_};
  if (combine.Run() != CombineChannelsError::kNone) {
    // Only a non-finite speech weight gets here: show the rest pose.
    std::fill(weights_.begin(), weights_.end(), 0.0f);
  }
}

}  // namespace facerig
