// The rig's images as OpenGL textures: each decoded once (OpenCV) and
// uploaded with mipmaps, base colours as sRGB, normal maps as linear data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::player {

// Decodes `image` into 8-bit RGBA (rows top to bottom). False, with `problem`
// naming the image, when the bytes do not decode or decode to another size
// than the header said.
bool DecodeRgba(const EncodedImage& image, cv::Mat* rgba, std::string* problem);

// Needs a current GL context for its whole life.
class RigTextures {
 public:
  // Uploads every image the rig's materials use, in the role they use it in
  // (an image used both ways is uploaded twice). An image that fails is left
  // out, named in problems(), and its parts draw with their colour alone.
  explicit RigTextures(const Rig& rig);
  ~RigTextures();
  RigTextures(const RigTextures&) = delete;
  RigTextures& operator=(const RigTextures&) = delete;

  // The texture of image `index` in its role; 0 when none (index -1, or it failed).
  unsigned base_colour(std::int32_t index) const { return Find(base_colour_, index); }
  unsigned normal(std::int32_t index) const { return Find(normal_, index); }
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  static unsigned Find(const std::vector<unsigned>& textures, std::int32_t index);

  std::vector<unsigned> base_colour_;  // per rig image; 0: not used as base colour, or failed
  std::vector<unsigned> normal_;
  std::vector<std::string> problems_;
};

}  // namespace facerig::player
