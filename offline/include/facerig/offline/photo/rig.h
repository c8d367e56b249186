// A talking head made from one photograph: the template rig on the photo's
// face (photo_fit.h), wearing the photo (photo_texture.h).
//
// The rig keeps the template's topology, parts and expression deltas; only
// its neutral changes to the fitted rest face. That is exact for a template
// linear in identity (ICT-FaceKit: every face is neutral + identity modes +
// expression deltas, the deltas the same for every identity) and a close
// approximation for the small, smooth deformation of the built-in head.
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "facerig/offline/photo/fit.h"
#include "facerig/offline/photo/texture.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// PhotoModelParams' expressions under the spelling `rig` uses (ICT's
// mouthSmile_L, ARKit's mouthSmileLeft, ...); names it lacks are left out.
PhotoModelParams PhotoModelParamsFor(const Rig& rig);

struct PhotoRigParams {
  PhotoTextureParams texture;
  PhotoSkinMaskParams mask;
  PhotoHairParams hair;
};

struct PhotoRig {
  Rig rig;                   // the template on the fitted face, textured
  PhotoTextureStats texture_stats;
  glm::vec3 skin_colour{0.0f};  // sRGB in [0, 1], estimated from the photo
  std::size_t eye_materials_painted = 0;
  // A deformed fit's eye-opening rim vertices put on the photo's lids (0: none).
  std::size_t lid_margins_fitted = 0;
  PhotoSkinMask skin_mask;  // where the texture took photo pixels (empty: everywhere)
  bool hair_found = false;  // the photo's hair told from the background: the scalp wears it
  glm::vec3 hair_colour{0.0f};  // sRGB in [0, 1], when found
};

// `surface`: the template's surface on the rig's vertices whose triangle t is
// the rig's triangle t (NeutralMesh(rig), or GroupedByPart of the OBJ a
// template folder was read from), with UVs. The photo is baked onto the face
// as the photo shows it (fit.posed_positions under fit.view), then the rig and
// surface take fit.rest_positions. A deformed fit (no identity modes) with
// landmarks first gets its lid margins onto the photo's lids (both faces). Placeholder materials become their part's
// role material and untextured eyes get painted ones (eye_textures.h), so
// eyes, teeth, tongue and lashes keep materials of their own. `landmarks`:
// the 68 points detected on the photo; the texture then takes photo pixels
// only where BuildPhotoSkinMask says they show the face's skin (empty: all).
// \throw InvalidInputError when the fit, surface and rig do not match, or as
//        BakePhotoTexture.
PhotoRig MakePhotoRig(const Rig& template_rig, Mesh surface, const PhotoFit& fit, const RgbImage& photo,
                      std::span<const glm::vec2> landmarks, const PhotoRigParams& params = {});

}  // namespace facerig
