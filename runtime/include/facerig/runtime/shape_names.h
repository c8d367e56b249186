// Matching rig shapes by ARKit-style name across naming styles
// ("mouthSmile_L", "mouthSmileLeft", "blendShape1.mouthSmile_L", ...), as the
// viseme mapping, the emotions and the gaze look shapes up.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

std::string LowerAscii(std::string_view text);

// Lower case, side suffix (left/right, _l/_r, .l/.r) split off as `side`,
// namespace prefix ("blendShape1.") removed.
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

}  // namespace facerig
