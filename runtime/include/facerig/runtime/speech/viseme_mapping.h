// Viseme weights -> rig (blend-shape) weights.
//
// A VisemeMapping is built once per rig: for each of the 15 visemes a short
// list of (shape index, weight, channel). Built-in mappings:
// - ARKit-named rigs (jawOpen, mouthClose, mouthPress_L / mouthPressLeft, ...;
//   names are matched case-insensitively, with `_L/_R`, `Left/Right` or `.L/.R`
//   sides and any `prefix.` namespace, e.g. "blendShape1.mouthSmileLeft");
// - rigs with one target per viseme ("viseme_PP", "viseme_aa", ... or "PP",
//   "aa", ...; case-insensitive; Oculus' "I", "O", "U" for ih, oh, ou).
// A user mapping file replaces the built-in list of the visemes it names.
// Missing shapes degrade: the mapping keeps what the rig has and reports a
// warning per missing shape; a rig with none of them gets an empty mapping
// (speech then leaves the face at rest) and a warning.
//
// The ARKit weights were measured on ICT-FaceKit (whose neutral has the lips
// together): PP presses the lips (inner-lip gap 0.1 mm vs 25 mm for aa) and
// uses no jawOpen; FF rolls the lower lip in under the raised upper lip with
// the jaw slightly open, so the upper incisor edge rests on the lower lip
// (within 0.1 mm).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/contribution_table.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/runtime/speech/viseme.h"

namespace facerig {

// Which JALI intensity scales a contribution: the jaw (jawOpen and the shapes
// that ride on it) or the lips (everything else).
enum class MappingChannel : std::uint8_t { kJaw, kLip };

struct ShapeContribution {
  std::uint32_t shape = 0;  // index into the rig's shapes
  float weight = 0.0f;      // rig weight at full viseme weight, in [0,1]
  MappingChannel channel = MappingChannel::kLip;
};

enum class VisemeMappingStyle : std::uint8_t {
  kAuto,       // per-viseme targets when the rig has them for at least 7 of the 14
               // non-silent visemes, else ARKit
  kArkit,
  kPerViseme,
};

// A mapping described by shape names, as in a mapping file.
struct NamedShapeWeight {
  std::string shape;
  float weight = 0.0f;
  // nullopt: kJaw for jawOpen / mouthClose / jawForward, kLip otherwise.
  std::optional<MappingChannel> channel;
};

// Per viseme: nullopt keeps the built-in list; a value (even empty) replaces it.
struct VisemeMappingOverrides {
  std::array<std::optional<std::vector<NamedShapeWeight>>, kVisemeCount> visemes;
};


struct VisemeMappingOptions {
  VisemeMappingStyle style = VisemeMappingStyle::kAuto;
  const VisemeMappingOverrides* overrides = nullptr;  // optional
};

// Immutable; built by BuildVisemeMapping for one rig.
class VisemeMapping {
 public:
  std::span<const ShapeContribution> contributions(Viseme viseme) const;
  // The shape count of the rig this mapping was built for.
  std::size_t rig_shape_count() const { return rig_shape_count_; }
  // The style actually used (never kAuto).
  VisemeMappingStyle style() const { return style_; }
  // True when no viseme moves any shape.
  bool empty() const { return table_.empty(); }

 private:
  friend struct VisemeMappingBuilder;
  ContributionTable<ShapeContribution, kVisemeCount> table_;
  std::size_t rig_shape_count_ = 0;
  VisemeMappingStyle style_ = VisemeMappingStyle::kArkit;
};

struct VisemeMappingResult {
  VisemeMapping mapping;
  std::vector<std::string> warnings;  // missing shapes, silent visemes; empty when all was found
};

// Builds the mapping for `rig`. Never throws for a rig lacking shapes (see
// warnings); duplicate shapes within one viseme keep the largest weight.
VisemeMappingResult BuildVisemeMapping(const Rig& rig, const VisemeMappingOptions& options = {});

// True for the jaw-channel shapes (jawOpen, mouthClose, jawForward), by ARKit name.
bool IsJawShapeName(std::string_view name);

enum class VisemeWeightsJobError : std::uint8_t {
  kNone,
  kNoMapping,
  kVisemeCountMismatch,  // viseme_weights.size() != kVisemeCount
  kNonFiniteViseme,      // a viseme weight is NaN, infinite or outside [0,1]
  kInvalidIntensity,     // jaw or lip intensity NaN, infinite or outside [0, 4]
  kWeightCountMismatch,  // out_weights.size() != mapping->rig_shape_count()
};

const char* ToString(VisemeWeightsJobError error);

// Viseme weights (CoarticulationJob's output) -> dense rig weights:
//   out[s] = base[s] + sum_v w_v * weight(v,s) * k(v,s),  clamped to [0,1],
// with base = 0 (accumulate = false: every shape is written) or the current
// out[s] (accumulate = true: only shapes the mapping touches are changed).
// k is jaw_intensity for kJaw contributions and lip_intensity for kLip ones,
// except for PP and FF, which are never scaled: closure and lip-teeth contact
// hold at any intensity. Owns no memory; Run() allocates nothing, throws
// nothing and takes no lock.
struct VisemeWeightsJob {
  const VisemeMapping* mapping = nullptr;
  std::span<const float> viseme_weights;  // kVisemeCount, each in [0,1]
  float jaw_intensity = 1.0f;  // JALI jaw: 0 = ventriloquist, 1 = as mapped, up to 4
  float lip_intensity = 1.0f;  // JALI lip
  bool accumulate = false;
  std::span<float> out_weights;  // mapping->rig_shape_count()

  VisemeWeightsJobError Validate() const;
  // Validates, then writes. On error the output is left untouched.
  VisemeWeightsJobError Run() const;
};

}  // namespace facerig
