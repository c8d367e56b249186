// Eye textures painted from the eyes' own geometry.
//
// A rig without textures draws its eyes in flat colours: in any glTF viewer
// ICT-FaceKit's eyeball (an opaque sclera over its iris mesh) is then a white
// ball, and an iris mesh a flat disc with no pupil. PaintEyeTextures gives
// each such eye material an image baked into its own UVs: sclera, a fibred
// iris with a darker limbus, and a pupil, placed around the eye's forward
// axis (from the eyeball's centre through its iris mesh, or its cornea); and
// lashes, drawn flat as dark bands, hairs in an alpha channel fanning out
// round that axis.
#pragma once

#include <cstddef>

#include "facerig/runtime/mesh.h"

namespace facerig {

struct EyeTextureParams {
  int size = 512;  // texels a side
  // The iris's angular radius on an eyeball: a 12 mm iris on a 24 mm eyeball.
  float iris_half_angle = 0.52f;
  // The pupil's radius over the iris's.
  float pupil_fraction = 0.4f;
};

// For every part whose role is sclera, iris or lashes (part_roles.h; lashes
// only when the mesh has eyeballs) and whose material has UVs but no
// base-colour image: paints an image for that
// material, sets its base colour to white (the image carries the colour) and
// returns how many materials it painted. A sclera carries the iris and pupil
// when the mesh has no pupil part (the iris mesh then lies under it); an iris
// part carries the pupil likewise. Other materials are left as they are.
// \throw InvalidInputError when the mesh is invalid (Mesh::Validate).
std::size_t PaintEyeTextures(Mesh& mesh, const EyeTextureParams& params = {});

}  // namespace facerig
