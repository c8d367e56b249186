#include "facerig/runtime/behaviour/emotion.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "facerig/runtime/enum_names.h"
#include "facerig/runtime/shape_names.h"

namespace facerig {
namespace {

constexpr std::array<std::string_view, kEmotionCount> kNames = {"joy",   "sadness",  "fear",
                                                                 "anger", "surprise", "disgust"};

struct RecipeEntry {
  Emotion emotion;
  const char* shape;
  float weight;
};

// Built-in ARKit recipes from the FACS action units of each basic emotion
// (Ekman & Friesen), AU -> ARKit shape:
//   joy      AU6 cheek raiser + AU12 lip corner puller (Duchenne smile)
//   sadness  AU1 inner brow raiser + AU4 brow lowerer + AU15 lip corner depressor (+AU17)
//   fear     AU1+2 brows up + AU4 + AU5 upper lid raiser + AU20 lip stretcher + AU26 jaw drop
//   anger    AU4 brow lowerer + AU5/7 lids + AU23/24 lip tightener/presser
//   surprise AU1+2 brows up + AU5 upper lid raiser + AU26 jaw drop
//   disgust  AU9 nose wrinkler + AU10 upper lip raiser + AU15 + AU17
// Weights stay below 1 so that emotions combine and speech adds on top before
// the [0,1] clamp. Shapes named with _L also mean _R (added automatically);
// browInnerUp resolves to both sides on rigs that split it (ICT-FaceKit).
constexpr RecipeEntry kRecipes[] = {
    {Emotion::kJoy, "mouthSmile_L", 0.80f},
    {Emotion::kJoy, "cheekSquint_L", 0.60f},
    {Emotion::kJoy, "eyeSquint_L", 0.40f},
    {Emotion::kJoy, "mouthDimple_L", 0.20f},
    {Emotion::kJoy, "mouthUpperUp_L", 0.15f},
    {Emotion::kSadness, "browInnerUp", 0.80f},
    {Emotion::kSadness, "browDown_L", 0.20f},
    {Emotion::kSadness, "mouthFrown_L", 0.70f},
    {Emotion::kSadness, "mouthShrugLower", 0.30f},
    {Emotion::kSadness, "mouthPress_L", 0.20f},
    {Emotion::kSadness, "eyeSquint_L", 0.10f},
    {Emotion::kFear, "browInnerUp", 0.80f},
    {Emotion::kFear, "browOuterUp_L", 0.40f},
    {Emotion::kFear, "eyeWide_L", 0.80f},
    {Emotion::kFear, "mouthStretch_L", 0.60f},
    {Emotion::kFear, "mouthLowerDown_L", 0.20f},
    {Emotion::kFear, "jawOpen", 0.15f},
    {Emotion::kAnger, "browDown_L", 0.90f},
    {Emotion::kAnger, "eyeSquint_L", 0.50f},
    {Emotion::kAnger, "eyeWide_L", 0.20f},
    {Emotion::kAnger, "mouthPress_L", 0.50f},
    {Emotion::kAnger, "mouthFrown_L", 0.30f},
    {Emotion::kAnger, "noseSneer_L", 0.30f},
    {Emotion::kSurprise, "browInnerUp", 0.80f},
    {Emotion::kSurprise, "browOuterUp_L", 0.80f},
    {Emotion::kSurprise, "eyeWide_L", 0.80f},
    {Emotion::kSurprise, "jawOpen", 0.25f},
    {Emotion::kDisgust, "noseSneer_L", 0.80f},
    {Emotion::kDisgust, "mouthUpperUp_L", 0.50f},
    {Emotion::kDisgust, "browDown_L", 0.40f},
    {Emotion::kDisgust, "mouthFrown_L", 0.40f},
    {Emotion::kDisgust, "cheekSquint_L", 0.30f},
    {Emotion::kDisgust, "mouthShrugLower", 0.30f},
    {Emotion::kDisgust, "eyeSquint_L", 0.30f},
};

// Measured on ICT-FaceKit: each opens the inner lips of a closed PP pose by
// 2.5 mm or more at weight 1 (see emotion.h). mouthPress is here too: added
// to the PP press it pushes the lips through each other (2.6 mm at 1.0), so
// during contact the speech alone owns the press.
constexpr std::string_view kLipOpeners[] = {
    "jawopen",        "jawforward",      "jaw_l",          "jaw_r",         "mouthclose",
    "mouthfunnel",    "mouthpucker",     "mouthrolllower", "mouthrollupper", "mouthshruglower",
    "mouthshrugupper", "mouthupperup",   "mouthlowerdown", "nosesneer",     "mouthpress",
};

// Lower case, side suffix and namespace prefix removed; jawLeft/jawRight are
// shapes of their own, not sides, and become "jaw_l"/"jaw_r".
std::string OpenerKey(std::string_view name) {
  const CanonicalShapeName canonical = CanonicalShapeNameOf(name);
  if (canonical.base == "jaw" && canonical.side != 0) return canonical.side == 'l' ? "jaw_l" : "jaw_r";
  return canonical.base;
}

}  // namespace

struct EmotionRigBuilder {
  ContributionTable<EmotionContribution, kEmotionCount>::Builder table;

  void Add(Emotion e, std::size_t shape, float weight, bool opens_lips) {
    table.Add(static_cast<std::size_t>(e), {static_cast<std::uint32_t>(shape), weight, opens_lips},
              [](EmotionContribution& existing, const EmotionContribution& c) {
                existing.weight = std::max(existing.weight, c.weight);
                existing.opens_lips = existing.opens_lips || c.opens_lips;
              });
  }

  EmotionRig Finish(std::size_t rig_shape_count) const {
    EmotionRig rig;
    rig.rig_shape_count_ = rig_shape_count;
    rig.table_ = table.Freeze();
    return rig;
  }
};

std::string_view ToString(Emotion emotion) { return EnumName(kNames, emotion); }

std::optional<Emotion> ParseEmotion(std::string_view name) { return EnumNamed<Emotion>(kNames, name); }

bool OpensLips(std::string_view arkit_name) {
  const std::string key = OpenerKey(arkit_name);
  return std::find(std::begin(kLipOpeners), std::end(kLipOpeners), key) != std::end(kLipOpeners);
}

std::span<const EmotionContribution> EmotionRig::contributions(Emotion emotion) const {
  return table_.of(static_cast<std::size_t>(emotion));
}


EmotionRigResult BuildEmotionRig(const Rig& rig, const EmotionOverrides* overrides) {
  EmotionRigResult result;
  EmotionRigBuilder builder;
  std::vector<std::string> missing;
  auto add = [&](Emotion e, const std::string& name, float weight, std::optional<bool> opens_lips) {
    for (std::size_t s : FindShapesNotingMissing(rig, name, missing)) builder.Add(e, s, weight, opens_lips.value_or(OpensLips(name)));
  };
  for (const RecipeEntry& r : kRecipes) {
    const auto e = static_cast<std::size_t>(r.emotion);
    if (overrides != nullptr && overrides->emotions[e]) continue;
    for (const std::string& name : WithRightTwin(r.shape)) add(r.emotion, name, r.weight, std::nullopt);
  }
  if (overrides != nullptr) {
    for (std::size_t e = 0; e < kEmotionCount; ++e) {
      if (!overrides->emotions[e]) continue;
      for (const NamedEmotionWeight& entry : *overrides->emotions[e]) {
        add(static_cast<Emotion>(e), entry.shape, entry.weight, entry.opens_lips);
      }
    }
  }
  for (const std::string& name : missing) result.warnings.push_back("emotions: rig has no shape " + name);
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    const bool replaced = overrides != nullptr && overrides->emotions[e].has_value();
    if (builder.table.list(e).empty() && !replaced) {
      result.warnings.push_back("emotion " + std::string(kNames[e]) + " moves no shape on this rig");
    }
  }
  result.emotions = builder.Finish(rig.shape_count());
  return result;
}

void EmotionState::SetTarget(Emotion emotion, float value) {
  const auto e = static_cast<std::size_t>(emotion);
  if (e >= kEmotionCount || std::isnan(value)) return;
  target[e] = std::clamp(value, 0.0f, 1.0f);
}

bool EmotionState::Advance(Seconds step) {
  const double dt = step.count();
  if (!(dt >= 0.0 && std::isfinite(dt))) return false;
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    if (!(attack[e] > 0.0f && std::isfinite(attack[e]) && release[e] > 0.0f && std::isfinite(release[e]))) {
      return false;
    }
  }
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    const double current = std::clamp(static_cast<double>(intensity[e]), 0.0, 1.0);
    const double goal = std::clamp(static_cast<double>(target[e]), 0.0, 1.0);
    double next = goal;
    if (goal > current) {
      next = std::min(goal, current + dt / static_cast<double>(attack[e]));
    } else if (goal < current) {
      next = std::max(goal, current - dt / static_cast<double>(release[e]));
    }
    intensity[e] = static_cast<float>(next);
  }
  return true;
}

const char* ToString(EmotionChannelsJobError error) {
  switch (error) {
    case EmotionChannelsJobError::kNone: return "no error";
    case EmotionChannelsJobError::kNoEmotions: return "no emotion rig";
    case EmotionChannelsJobError::kIntensityCountMismatch: return "intensity count is not 6";
    case EmotionChannelsJobError::kInvalidIntensity:
      return "an intensity or lip_contact is NaN, infinite or outside [0,1]";
    case EmotionChannelsJobError::kValueCountMismatch: return "output size differs from the emotion channel count";
  }
  return "unknown error";
}

EmotionChannelsJobError EmotionChannelsJob::Validate() const {
  if (emotions == nullptr) return EmotionChannelsJobError::kNoEmotions;
  if (intensities.size() != kEmotionCount) return EmotionChannelsJobError::kIntensityCountMismatch;
  for (float i : intensities) {
    if (!(i >= 0.0f && i <= 1.0f)) return EmotionChannelsJobError::kInvalidIntensity;
  }
  if (!(lip_contact >= 0.0f && lip_contact <= 1.0f)) return EmotionChannelsJobError::kInvalidIntensity;
  if (out_values.size() != emotions->channel_count()) return EmotionChannelsJobError::kValueCountMismatch;
  return EmotionChannelsJobError::kNone;
}

EmotionChannelsJobError EmotionChannelsJob::Run() const {
  if (const EmotionChannelsJobError e = Validate(); e != EmotionChannelsJobError::kNone) return e;
  const float keep_opening = 1.0f - lip_contact;
  std::size_t next = 0;
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    const float intensity = intensities[e];
    for (const EmotionContribution& c : emotions->contributions(static_cast<Emotion>(e))) {
      out_values[next++] = {c.shape, intensity * c.weight * (c.opens_lips ? keep_opening : 1.0f)};
    }
  }
  return EmotionChannelsJobError::kNone;
}

}  // namespace facerig
