#include "facerig/runtime/speech/viseme_mapping.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace facerig {
namespace {

struct ArkitEntry {
  Viseme viseme;
  const char* shape;
  float weight;
  // Used where the rig has it, without a warning where not: the tongue.
  bool optional = false;
};

// The built-in ARKit mapping. Values measured on ICT-FaceKit (cm; inner-lip gap
// = closest distance between the upper and lower inner-lip midline vertices):
// neutral 0.8 mm, PP 0.1 mm, aa 24.9 mm, oh 22.7 mm, E 14.7 mm, ou 8.7 mm.
// - PP uses only mouthPress: the neutral already has the lips together and any
//   jawOpen would have to be cancelled by mouthClose, which overshoots (the
//   lips pass through each other on ICT at equal weights).
// - FF: mouthRollLower 0.2 + jawOpen 0.05 put the lower lip's contact line
//   on the upper incisor edge (0.07 mm away); mouthUpperUp shows the teeth.
//   FF is sensitive to jawOpen (0.1 moves the lip 1.8 mm away), which is why
//   PP and FF are exempt from the jaw/lip intensities.
// - Vowels: jawOpen carries the opening (aa > oh > E > ih), lips add spread
//   (mouthStretch, mouthSmile) or rounding (mouthFunnel, mouthPucker).
// Shapes named with _L also mean _R (added automatically).
constexpr ArkitEntry kArkitMapping[] = {
    {Viseme::kPP, "mouthPress_L", 0.30f},
    {Viseme::kFF, "mouthRollLower", 0.20f},
    {Viseme::kFF, "mouthUpperUp_L", 0.20f},
    {Viseme::kFF, "jawOpen", 0.05f},
    {Viseme::kTH, "jawOpen", 0.12f},
    {Viseme::kTH, "mouthUpperUp_L", 0.10f},
    {Viseme::kTH, "mouthLowerDown_L", 0.10f},
    {Viseme::kTH, "tongueOut", 0.45f, true},
    {Viseme::kDD, "jawOpen", 0.15f},
    {Viseme::kDD, "mouthStretch_L", 0.15f},
    {Viseme::kDD, "mouthUpperUp_L", 0.05f},
    {Viseme::kDD, "tongueOut", 0.10f, true},
    {Viseme::kKK, "jawOpen", 0.20f},
    {Viseme::kKK, "mouthStretch_L", 0.15f},
    {Viseme::kCH, "jawOpen", 0.10f},
    {Viseme::kCH, "mouthFunnel", 0.50f},
    {Viseme::kCH, "mouthPucker", 0.20f},
    {Viseme::kCH, "mouthUpperUp_L", 0.10f},
    {Viseme::kSS, "jawOpen", 0.05f},
    {Viseme::kSS, "mouthStretch_L", 0.35f},
    {Viseme::kSS, "mouthSmile_L", 0.10f},
    {Viseme::kSS, "mouthUpperUp_L", 0.10f},
    {Viseme::kNN, "jawOpen", 0.12f},
    {Viseme::kNN, "mouthStretch_L", 0.10f},
    {Viseme::kRR, "jawOpen", 0.10f},
    {Viseme::kRR, "mouthFunnel", 0.30f},
    {Viseme::kRR, "mouthPucker", 0.30f},
    {Viseme::kAA, "jawOpen", 0.60f},
    {Viseme::kAA, "mouthLowerDown_L", 0.20f},
    {Viseme::kAA, "mouthUpperUp_L", 0.10f},
    {Viseme::kE, "jawOpen", 0.35f},
    {Viseme::kE, "mouthStretch_L", 0.30f},
    {Viseme::kE, "mouthLowerDown_L", 0.20f},
    {Viseme::kE, "mouthSmile_L", 0.10f},
    {Viseme::kIH, "jawOpen", 0.20f},
    {Viseme::kIH, "mouthStretch_L", 0.40f},
    {Viseme::kIH, "mouthSmile_L", 0.20f},
    {Viseme::kOH, "jawOpen", 0.40f},
    {Viseme::kOH, "mouthFunnel", 0.60f},
    {Viseme::kOU, "jawOpen", 0.15f},
    {Viseme::kOU, "mouthPucker", 0.80f},
    {Viseme::kOU, "mouthFunnel", 0.30f},
};


std::optional<std::size_t> FindVisemeTarget(const Rig& rig, Viseme v) {
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    if (VisemeOfTargetName(rig.shape_name(s)) == v) return s;
  }
  return std::nullopt;
}

}  // namespace

// Accumulates contributions per viseme, then freezes them into a mapping.
struct VisemeMappingBuilder {
  ContributionTable<ShapeContribution, kVisemeCount>::Builder table;

  void Add(Viseme v, std::size_t shape, float weight, MappingChannel channel) {
    table.Add(static_cast<std::size_t>(v), {static_cast<std::uint32_t>(shape), weight, channel},
              [](ShapeContribution& existing, const ShapeContribution& c) {
                existing.weight = std::max(existing.weight, c.weight);
              });
  }

  VisemeMapping Finish(std::size_t rig_shape_count, VisemeMappingStyle style) const {
    VisemeMapping m;
    m.rig_shape_count_ = rig_shape_count;
    m.style_ = style;
    m.table_ = table.Freeze();
    return m;
  }
};

std::span<const ShapeContribution> VisemeMapping::contributions(Viseme viseme) const {
  return table_.of(static_cast<std::size_t>(viseme));
}

bool IsJawShapeName(std::string_view name) {
  const std::string c = CanonicalShapeNameOf(name).full();
  return c == "jawopen" || c == "mouthclose" || c == "jawforward";
}



VisemeMappingResult BuildVisemeMapping(const Rig& rig, const VisemeMappingOptions& options) {
  VisemeMappingResult result;
  VisemeMappingBuilder builder;

  std::array<std::optional<std::size_t>, kVisemeCount> targets;
  std::size_t target_count = 0;
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    targets[v] = FindVisemeTarget(rig, static_cast<Viseme>(v));
    if (targets[v] && v != static_cast<std::size_t>(Viseme::kSil)) ++target_count;
  }
  bool any_arkit = false;
  for (const ArkitEntry& e : kArkitMapping) {
    if (!FindShapesByArkitName(rig, e.shape).empty()) any_arkit = true;
  }
  VisemeMappingStyle style = options.style;
  if (style == VisemeMappingStyle::kAuto) {
    style = (target_count >= (kVisemeCount - 1) / 2 || (target_count > 0 && !any_arkit))
                ? VisemeMappingStyle::kPerViseme
                : VisemeMappingStyle::kArkit;
  }

  if (style == VisemeMappingStyle::kPerViseme) {
    for (std::size_t v = 0; v < kVisemeCount; ++v) {
      const auto viseme = static_cast<Viseme>(v);
      if (targets[v]) {
        // Open vowels are carried by the jaw; everything else by the lips.
        const bool jaw = viseme == Viseme::kAA || viseme == Viseme::kE || viseme == Viseme::kIH ||
                         viseme == Viseme::kOH;
        builder.Add(viseme, *targets[v], 1.0f, jaw ? MappingChannel::kJaw : MappingChannel::kLip);
      } else if (viseme != Viseme::kSil) {
        result.warnings.push_back("rig has no target for viseme " + std::string(ToString(viseme)) +
                                  " (looked for viseme_" + std::string(ToString(viseme)) + " or " +
                                  std::string(ToString(viseme)) + ", any case)");
      }
    }
  } else {
    std::vector<std::string> missing;
    for (const ArkitEntry& e : kArkitMapping) {
      for (const std::string& name : WithRightTwin(e.shape)) {
        const std::vector<std::size_t> found =
            e.optional ? FindShapesByArkitName(rig, name) : FindShapesNotingMissing(rig, name, missing);
        const MappingChannel channel = IsJawShapeName(name) ? MappingChannel::kJaw : MappingChannel::kLip;
        for (std::size_t s : found) builder.Add(e.viseme, s, e.weight, channel);
      }
    }
    for (const std::string& name : missing) {
      result.warnings.push_back("ARKit viseme mapping: rig has no shape " + name);
    }
  }

  if (options.overrides != nullptr) {
    for (std::size_t v = 0; v < kVisemeCount; ++v) {
      const auto& list = options.overrides->visemes[v];
      if (!list) continue;
      const auto viseme = static_cast<Viseme>(v);
      builder.table.list(v).clear();
      for (const NamedShapeWeight& entry : *list) {
        const std::vector<std::size_t> found = FindShapesByArkitName(rig, entry.shape);
        if (found.empty()) {
          result.warnings.push_back("mapping for viseme " + std::string(ToString(viseme)) +
                                    ": rig has no shape " + entry.shape);
        }
        const MappingChannel channel = entry.channel.value_or(
            IsJawShapeName(entry.shape) ? MappingChannel::kJaw : MappingChannel::kLip);
        for (std::size_t s : found) builder.Add(viseme, s, entry.weight, channel);
      }
    }
  }

  for (std::size_t v = 1; v < kVisemeCount; ++v) {
    const auto viseme = static_cast<Viseme>(v);
    const bool replaced = options.overrides != nullptr && options.overrides->visemes[v].has_value();
    if (builder.table.list(v).empty() && !replaced) {
      // PP still closes on a rig whose neutral is closed: the contact pass
      // zeroes every other viseme.
      result.warnings.push_back("viseme " + std::string(ToString(viseme)) +
                                " moves no shape on this rig");
    }
  }
  result.mapping = builder.Finish(rig.shape_count(), style);
  if (result.mapping.empty()) {
    result.warnings.push_back("no viseme moves any shape: the rig has neither ARKit mouth shapes "
                              "nor per-viseme targets, so speech leaves the face at rest");
  }
  return result;
}

const char* ToString(VisemeWeightsJobError error) {
  switch (error) {
    case VisemeWeightsJobError::kNone: return "no error";
    case VisemeWeightsJobError::kNoMapping: return "no mapping";
    case VisemeWeightsJobError::kVisemeCountMismatch: return "viseme weight count is not 15";
    case VisemeWeightsJobError::kNonFiniteViseme: return "a viseme weight is NaN, infinite or outside [0,1]";
    case VisemeWeightsJobError::kInvalidIntensity: return "jaw or lip intensity is NaN, infinite or outside [0,4]";
    case VisemeWeightsJobError::kWeightCountMismatch: return "out_weights size differs from the rig's shape count";
  }
  return "unknown error";
}

VisemeWeightsJobError VisemeWeightsJob::Validate() const {
  if (mapping == nullptr) return VisemeWeightsJobError::kNoMapping;
  if (viseme_weights.size() != kVisemeCount) return VisemeWeightsJobError::kVisemeCountMismatch;
  for (float w : viseme_weights) {
    if (!(w >= 0.0f && w <= 1.0f)) return VisemeWeightsJobError::kNonFiniteViseme;
  }
  for (float k : {jaw_intensity, lip_intensity}) {
    if (!(k >= 0.0f && k <= 4.0f)) return VisemeWeightsJobError::kInvalidIntensity;
  }
  if (out_weights.size() != mapping->rig_shape_count()) return VisemeWeightsJobError::kWeightCountMismatch;
  return VisemeWeightsJobError::kNone;
}

VisemeWeightsJobError VisemeWeightsJob::Run() const {
  if (const VisemeWeightsJobError e = Validate(); e != VisemeWeightsJobError::kNone) return e;
  if (!accumulate) std::fill(out_weights.begin(), out_weights.end(), 0.0f);
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const float w = viseme_weights[v];
    if (w == 0.0f) continue;
    const auto viseme = static_cast<Viseme>(v);
    const bool contact = viseme == Viseme::kPP || viseme == Viseme::kFF;
    for (const ShapeContribution& c : mapping->contributions(viseme)) {
      const float k = contact ? 1.0f : (c.channel == MappingChannel::kJaw ? jaw_intensity : lip_intensity);
      out_weights[c.shape] += w * c.weight * k;
    }
  }
  // Clamp only what this job touched, so other layers' weights stay as they were.
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    for (const ShapeContribution& c : mapping->contributions(static_cast<Viseme>(v))) {
      out_weights[c.shape] = std::clamp(out_weights[c.shape], 0.0f, 1.0f);
    }
  }
  return VisemeWeightsJobError::kNone;
}

}  // namespace facerig
