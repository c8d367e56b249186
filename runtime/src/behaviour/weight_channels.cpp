#include "facerig/runtime/behaviour/weight_channels.h"

#include <algorithm>
#include <cmath>

namespace facerig {

const char* ToString(CombineChannelsError error) {
  switch (error) {
    case CombineChannelsError::kNone: return "no error";
    case CombineChannelsError::kWeightCountMismatch: return "base and output weights differ in size";
    case CombineChannelsError::kShapeOutOfRange: return "a weight channel names a shape the rig does not have";
    case CombineChannelsError::kInvalidValue:
      return "a base weight or channel value is NaN or infinite, or a channel value is outside [0,1]";
  }
  return "unknown error";
}

CombineChannelsError CombineChannelsJob::Validate() const {
  if (base.size() != out_weights.size()) return CombineChannelsError::kWeightCountMismatch;
  for (float w : base) {
    if (!std::isfinite(w)) return CombineChannelsError::kInvalidValue;
  }
  for (const ChannelLayer& layer : layers) {
    for (const ChannelValue& channel : layer.values) {
      if (channel.shape >= out_weights.size()) return CombineChannelsError::kShapeOutOfRange;
      if (!(channel.value >= 0.0f && channel.value <= 1.0f)) return CombineChannelsError::kInvalidValue;
    }
  }
  return CombineChannelsError::kNone;
}

CombineChannelsError CombineChannelsJob::Run() const {
  if (const CombineChannelsError e = Validate(); e != CombineChannelsError::kNone) return e;
  if (base.data() != out_weights.data()) std::copy(base.begin(), base.end(), out_weights.begin());
  for (const ChannelLayer& layer : layers) {
    if (layer.rule == ChannelRule::kMax) {
      for (const ChannelValue& c : layer.values) out_weights[c.shape] = std::max(out_weights[c.shape], c.value);
    } else {
      for (const ChannelValue& c : layer.values) out_weights[c.shape] += c.value;
      for (float& w : out_weights) w = std::clamp(w, 0.0f, 1.0f);
    }
  }
  for (float& w : out_weights) {
    if (w < zero_below) w = 0.0f;
  }
  return CombineChannelsError::kNone;
}

}  // namespace facerig
