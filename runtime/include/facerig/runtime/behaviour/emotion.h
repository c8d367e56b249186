// Emotions: the six basic expressions (Ekman) as per-rig weight recipes, an
// EmotionState that moves each intensity toward its target with attack and
// release times, and the EmotionChannelsJob that turns them into weight
// channels layered over speech (weight_channels.h, rule kAdd).
//
// Layering (EmotionChannelsJob, then CombineChannelsJob with speech as base):
//   final[s] = clamp01(speech[s] + sum_e I_e * weight(e,s) * k_s),
//   k_s = 1 - lip_contact   for shapes that open the lips,   1 otherwise,
// where lip_contact = LipContactWeight(viseme weights) (coarticulation.h) is 1
// exactly when the speech needs closed lips (p/b/m) or the lower lip on the
// upper teeth (f/v). So a smile stays on while the lips close, but a surprised
// jaw drop or a disgusted upper-lip raise gives way for the length of the
// contact. Which shapes open the lips was measured on ICT-FaceKit (adding the
// shape at weight 1 to a closed-lip PP pose): jaw*, mouthClose, mouthFunnel,
// mouthPucker, mouthRoll*, mouthShrug*, mouthUpperUp*, mouthLowerDown*,
// noseSneer* each open the inner lips by 2.5-42 mm, and mouthPress* on top of
// the PP press pushes the lips through each other (2.6 mm), so all of these
// give way; mouthSmile, mouthStretch, mouthDimple, mouthFrown, mouthLeft/Right
// and cheek* move the closed lips by at most 1.4 mm and keep their full weight.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/behaviour/weight_channels.h"
#include "facerig/runtime/contribution_table.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/seconds.h"

namespace facerig {

enum class Emotion : std::uint8_t { kJoy, kSadness, kFear, kAnger, kSurprise, kDisgust };
inline constexpr std::size_t kEmotionCount = 6;

// "joy", "sadness", "fear", "anger", "surprise", "disgust".
std::string_view ToString(Emotion emotion);
std::optional<Emotion> ParseEmotion(std::string_view name);

// True for shapes that open the lips (see above), by ARKit name (any side style).
bool OpensLips(std::string_view arkit_name);

struct EmotionContribution {
  std::uint32_t shape = 0;  // index into the rig's shapes
  float weight = 0.0f;      // rig weight at intensity 1, in [0,1]
  bool opens_lips = false;  // suppressed while the speech holds lip contact
};

// A recipe described by shape names, as in an emotion file.
struct NamedEmotionWeight {
  std::string shape;
  float weight = 0.0f;
  std::optional<bool> opens_lips;  // nullopt: OpensLips(shape)
};

// Per emotion: nullopt keeps the built-in recipe; a value (even empty) replaces it.
struct EmotionOverrides {
  std::array<std::optional<std::vector<NamedEmotionWeight>>, kEmotionCount> emotions;
};


// The emotions' recipes resolved for one rig. Immutable.
class EmotionRig {
 public:
  std::span<const EmotionContribution> contributions(Emotion emotion) const;
  std::size_t rig_shape_count() const { return rig_shape_count_; }
  // Contributions of all emotions: the size of EmotionChannelsJob's output.
  std::size_t channel_count() const { return table_.size(); }
  bool empty() const { return table_.empty(); }

 private:
  friend struct EmotionRigBuilder;
  ContributionTable<EmotionContribution, kEmotionCount> table_;
  std::size_t rig_shape_count_ = 0;
};

struct EmotionRigResult {
  EmotionRig emotions;
  std::vector<std::string> warnings;  // missing shapes; empty when all was found
};

// Resolves the built-in ARKit recipes (or the overrides) on `rig`, with the
// same name matching as the viseme mapping (FindShapesByArkitName). A rig
// lacking shapes degrades with warnings; never throws.
EmotionRigResult BuildEmotionRig(const Rig& rig, const EmotionOverrides* overrides = nullptr);

// Current emotion intensities, moved toward their targets by Advance(): up at
// 1/attack per second, down at 1/release per second (linear, so a target is
// reached exactly, in at most attack or release seconds for a full swing).
// Plain data, no allocation; one per character.
struct EmotionState {
  std::array<float, kEmotionCount> intensity{};  // current, [0,1]
  std::array<float, kEmotionCount> target{};     // [0,1]
  // Seconds for a 0 -> 1 rise / 1 -> 0 fall. Surprise is the briefest
  // expression (fast onset and offset); sadness builds and fades slowly.
  std::array<float, kEmotionCount> attack = {0.35f, 0.8f, 0.2f, 0.3f, 0.12f, 0.3f};
  std::array<float, kEmotionCount> release = {0.8f, 1.5f, 0.6f, 0.8f, 0.5f, 0.7f};

  // Sets a target (clamped to [0,1]; NaN is ignored).
  void SetTarget(Emotion emotion, float value);
  // Moves every intensity toward its target by dt seconds. Returns false and
  // changes nothing when dt is negative or not finite, or an attack/release
  // time is not positive and finite.
  bool Advance(Seconds dt);
};

enum class EmotionChannelsJobError : std::uint8_t {
  kNone,
  kNoEmotions,
  kIntensityCountMismatch,  // intensities.size() != kEmotionCount
  kInvalidIntensity,        // an intensity or lip_contact NaN, infinite or outside [0,1]
  kValueCountMismatch,      // out_values.size() != emotions->channel_count()
};

const char* ToString(EmotionChannelsJobError error);

// The emotions' weight channels (see the formula at the top): one value per
// contribution of the EmotionRig, in its order; combine them over speech with
// ChannelRule::kAdd. Owns no memory; Run() allocates nothing, throws nothing,
// takes no lock.
struct EmotionChannelsJob {
  const EmotionRig* emotions = nullptr;
  std::span<const float> intensities;  // kEmotionCount (EmotionState::intensity)
  float lip_contact = 0.0f;            // LipContactWeight(viseme weights)
  std::span<ChannelValue> out_values;  // emotions->channel_count()

  EmotionChannelsJobError Validate() const;
  // Validates, then writes. On error the output is left untouched.
  EmotionChannelsJobError Run() const;
};

}  // namespace facerig
