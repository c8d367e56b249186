// The shape names and viseme targets a written rig carries, for engines and
// web players that look shapes up by Apple ARKit's 52 names and animate
// speech through the 15 Oculus / Meta viseme targets.
//
// Names: each shape the runtime matches to an ARKit name (shape_names.h: any
// case, _L/_R, .L/.R, Left/Right, a namespace) is renamed to Apple's spelling
// (kArkit) or ICT-FaceKit's `_L/_R` spelling (kIct); kKeep leaves every name.
// Under kArkit an unsided ARKit shape the rig has only per side (ICT's
// browInnerUp_L + browInnerUp_R) becomes one shape, the sum of its halves.
// Shapes that are not ARKit keep their names.
//
// Visemes: kOculus bakes viseme_sil ... viseme_U, each the weighted sum of the
// rig's shapes under the runtime's built-in ARKit viseme mapping
// (viseme_mapping.h), replacing viseme targets the rig already had; a rig
// without ARKit mouth shapes keeps its own targets, renamed to the Oculus
// spelling. kNone adds none (the rig's own pass through).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

enum class ShapeNaming : std::uint8_t { kArkit, kIct, kKeep };
enum class VisemeTargets : std::uint8_t { kOculus, kNone };

// "arkit", "ict", "keep"; "oculus", "none". nullopt for anything else.
std::optional<ShapeNaming> ParseShapeNaming(std::string_view text);
std::optional<VisemeTargets> ParseVisemeTargets(std::string_view text);
const char* ToString(ShapeNaming naming);
const char* ToString(VisemeTargets visemes);

struct StandardShapesOptions {
  ShapeNaming names = ShapeNaming::kArkit;
  VisemeTargets visemes = VisemeTargets::kOculus;
};

struct StandardShapesReport {
  std::size_t renamed = 0;                   // shapes whose name changed
  std::vector<std::string> merged;           // ARKit names made from a left and a right half
  // Of the 52 ARKit names, how many the result has (under kArkit: spelled
  // exactly; else: any spelling the runtime matches), and the others.
  std::size_t arkit_present = 0;
  std::vector<std::string> arkit_missing;
  std::size_t visemes_baked = 0;             // 15, or 0 when none were baked
  std::size_t viseme_targets = 0;            // viseme targets in the result (baked or the rig's own)
  std::vector<std::string> warnings;         // name clashes, the viseme mapping's missing shapes
};

struct StandardShapesResult {
  Rig rig;
  StandardShapesReport report;
};

// The rig with its shapes named and its visemes baked as `options` say;
// everything else (vertices, parts, materials, images, units) unchanged.
// \throw std::runtime_error if the result is not a valid rig (cannot happen
// for a valid input).
StandardShapesResult StandardizeShapes(const Rig& rig, const StandardShapesOptions& options = {});

// The rig without the viseme targets StandardizeShapes would bake again from
// its ARKit mouth shapes (so a transfer need not carry them); a rig without
// those shapes keeps its targets. `removed` (optional) gets how many went.
Rig WithoutBakedVisemes(const Rig& rig, std::size_t* removed = nullptr);

}  // namespace facerig
