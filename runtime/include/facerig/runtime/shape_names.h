// Matching rig shapes by ARKit-style name across naming styles
// ("mouthSmile_L", "mouthSmileLeft", "blendShape1.mouthSmile_L", ...), as the
// viseme mapping, the emotions and the gaze look shapes up.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

// Apple ARKit's 52 blend-shape names (ARFaceAnchor.BlendShapeLocation), in
// Apple's order. "Left" is the character's left (+X on the built-in head).
inline constexpr std::size_t kArkitShapeCount = 52;
extern const std::array<std::string_view, kArkitShapeCount> kArkitShapeNames;

// The ICT-FaceKit spelling of an ARKit name: "eyeBlinkLeft" -> "eyeBlink_L";
// names without a side, and jawLeft / jawRight / mouthLeft / mouthRight
// (motions, not sides), are unchanged.
std::string IctShapeName(std::string_view arkit_name);

// Lower case, side suffix (left/right, _l/_r, .l/.r) split off as `side`,
// namespace prefix ("blendShape1.", "head:", "mesh|") removed.
struct CanonicalShapeName {
  std::string base;
  char side = 0;  // 'l', 'r' or 0
  std::string full() const { return side ? base + '_' + side : base; }
};
CanonicalShapeName CanonicalShapeNameOf(std::string_view name);

// `name`, and then its right-side twin when it ends in "_L": the built-in
// recipes name the left side and mean both.
std::vector<std::string> WithRightTwin(std::string_view name);

// Shape lookup by ARKit-style name: exact name first, then case-insensitive
// with side suffixes and namespaces normalised. A name without a side that
// the rig only has per side ("browInnerUp" on a rig with browInnerUp_L/_R)
// returns both; a sided name on a rig without sides returns the unsided
// shape. Empty when nothing matches.
std::vector<std::size_t> FindShapesByArkitName(const Rig& rig, std::string_view name);
// The same, adding `name` to `missing` (once) when nothing matches, for the
// builders' "rig has no shape ..." warnings.
std::vector<std::size_t> FindShapesNotingMissing(const Rig& rig, const std::string& name,
                                                 std::vector<std::string>& missing);

// How a rig's shape answered an ARKit name (FindShapesByArkitName's steps).
enum class ShapeMatchKind : std::uint8_t {
  kExact,      // the same spelling
  kSpelling,   // another spelling of it: case, _L/_R, .L/.R, Left/Right, a namespace
  kBothSides,  // an unsided ARKit name answered by the rig's left and right halves
  kUnsided,    // a sided ARKit name answered by a shape without sides
};
const char* ToString(ShapeMatchKind kind);

struct ArkitShapeMatch {
  std::string_view arkit_name;
  std::vector<std::size_t> shapes;  // rig shape indices (two for kBothSides)
  ShapeMatchKind kind = ShapeMatchKind::kExact;
};

// What a rig's shape names mean to the runtime: the ARKit names it answers,
// those it lacks, its per-viseme targets, and the shapes that are neither.
struct ShapeNameReport {
  std::vector<ArkitShapeMatch> matched;    // in Apple's order
  std::vector<std::string_view> missing;   // ARKit names nothing answers
  std::vector<std::size_t> viseme_targets;  // shapes VisemeOfTargetName recognises
  std::vector<std::size_t> other;          // shapes neither ARKit nor viseme targets
};
ShapeNameReport MatchShapeNames(const Rig& rig);

}  // namespace facerig
