// Where a photo shows the head and its hair, for the photo texture's scalp.
#pragma once

#include <span>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/skin_mask.h"
#include "facerig/offline/render/rasterizer.h"

namespace facerig {

// Where the photo shows the head (face and hair, not the background), from
// GrabCut on a scaled copy of the window round the face, seeded from the
// landmarks (inside the jaw line: head; the window's edges inside the photo:
// background); and the hair's colour there.
struct PhotoHairParams {
  int work_size = 192;  // pixels a side of the scaled copy GrabCut runs on
  int iterations = 3;
};

struct PhotoHair {
  // Per photo pixel, the weight with which it shows the head (hair or skin);
  // empty when the head could not be told from the background.
  PhotoSkinMask head;
  glm::vec3 colour{0.0f};  // sRGB in [0, 1]: the median of the head's pixels above the brows that are not skin
  bool found = false;      // enough such pixels for a colour
};

// `skin`: BuildPhotoSkinMask of the same photo and landmarks.
// \throw InvalidInputError when landmarks.size() != 68 or the photo's pixels do not match its size.
PhotoHair FindPhotoHair(const RgbImage& photo, std::span<const glm::vec2> landmarks, const PhotoSkinMask& skin,
                        const PhotoHairParams& params = {});

}  // namespace facerig
