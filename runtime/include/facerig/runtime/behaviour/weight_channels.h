// How behaviours reach the rig weights: the speech's dense weights (visemes
// mapped to the rig, VisemeWeightsJob) are the base, and every other
// behaviour (emotions, blinks, gaze) writes values into channels (rig shapes
// found by name when the CharacterRig is built), each layer with a blend
// rule. CombineChannelsJob is the one place that merges them.
#pragma once

#include <cstdint>
#include <span>

namespace facerig {

enum class ChannelRule : std::uint8_t {
  kAdd,  // value added to the weight; after the layer every weight is clamped to [0,1]
  kMax,  // the larger of weight and value: a blink closes the lid whatever the emotion
};

// One value for one rig shape.
struct ChannelValue {
  std::uint32_t shape = 0;  // index into the rig's shapes
  float value = 0.0f;       // in [0,1]
  friend bool operator==(const ChannelValue&, const ChannelValue&) = default;
};

struct ChannelLayer {
  ChannelRule rule = ChannelRule::kAdd;
  std::span<const ChannelValue> values;
};

enum class CombineChannelsError : std::uint8_t {
  kNone,
  kWeightCountMismatch,  // base and out_weights differ in size
  kShapeOutOfRange,      // a channel names a shape the rig does not have
  kInvalidValue,         // a base weight or channel value NaN or infinite, or a value outside [0,1]
};

const char* ToString(CombineChannelsError error);

// base -> out_weights, then each layer in order, then weights below
// `zero_below` set to 0 (the blend skips them). Run() allocates nothing,
// throws nothing and takes no lock; O(shapes * layers + values).
struct CombineChannelsJob {
  std::span<const float> base;  // rig shape count; may alias out_weights
  std::span<const ChannelLayer> layers;
  float zero_below = 0.0f;
  std::span<float> out_weights;  // rig shape count

  CombineChannelsError Validate() const;
  // Validates, then writes. On error the output is left untouched.
  CombineChannelsError Run() const;
};

}  // namespace facerig
