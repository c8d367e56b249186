// Where a photo shows the face's skin, from dlib's 68 landmarks and the
// cheeks' colour: the photo texture takes photo pixels only there.
#pragma once

#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "facerig/offline/render/rasterizer.h"

namespace facerig {

// Where the photo shows the face's skin: a weight in [0, 1] per photo pixel
// over a window of the photo (0 outside it). Photo pixels count for the
// texture (directly and mirrored) only by this weight, so the background
// beside the face, hair and the inside of an open mouth never land on the
// skin. An empty mask lets every pixel count.
struct PhotoSkinMask {
  int left = 0, top = 0, width = 0, height = 0;  // the window, photo pixels
  std::vector<float> weight;  // width x height, row-major

  bool empty() const { return weight.empty(); }
  float At(int x, int y) const;
};

struct PhotoSkinMaskParams {
  // How far the forehead reaches above the brows, as a fraction of the
  // brows' height above the chin (a face's thirds: about one half).
  float forehead = 0.5f;
  // The soft edge's width as a fraction of the face size (the 68 points' box).
  float softness = 0.025f;
  // CIELAB distance from the cheeks' colour at which a pixel outside the
  // inner face stops counting as skin, from full to none. Lightness counts
  // less (shading), a* and b* more: blond or brown hair is as light as
  // shaded skin but yellower and less red.
  float skin_distance_full = 12.0f, skin_distance_none = 20.0f;
  float lightness_weight = 0.4f, chroma_weight = 1.5f;
};

// The mask of dlib's 68 landmarks on the photo: inside the jaw line extended
// up to the forehead, softly edged; between the inner face (brows, eyes, nose
// and mouth, trusted whatever their colour) and that outline only pixels near
// the cheeks' colour; none inside the inner lips (60-67: teeth and the dark
// of an open mouth).
// \throw InvalidInputError when landmarks.size() != 68 or the photo's pixels do not match its size.
PhotoSkinMask BuildPhotoSkinMask(const RgbImage& photo, std::span<const glm::vec2> landmarks,
                                 const PhotoSkinMaskParams& params = {});

// For looking at: the photo darkened and tinted blue where the mask leaves
// it out (by 1 - weight). \pre the mask empty or of this photo.
RgbImage ShadeOutsideSkinMask(const RgbImage& photo, const PhotoSkinMask& mask);

}  // namespace facerig
