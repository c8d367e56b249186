#include "facerig/runtime/material.h"

namespace facerig {

const char* ToString(AlphaMode mode) {
  switch (mode) {
    case AlphaMode::kOpaque: return "OPAQUE";
    case AlphaMode::kMask: return "MASK";
    case AlphaMode::kBlend: return "BLEND";
  }
  return "OPAQUE";
}

const char* MimeType(ImageFormat format) { return format == ImageFormat::kJpeg ? "image/jpeg" : "image/png"; }

const char* FileExtension(ImageFormat format) { return format == ImageFormat::kJpeg ? ".jpg" : ".png"; }

bool ValidateMaterials(const std::vector<Material>& materials, const std::vector<EncodedImage>& images,
                       std::string* problem) {
  const auto fail = [&](std::string text) {
    if (problem) *problem = std::move(text);
    return false;
  };
  const auto image_ok = [&](std::int32_t index) {
    return index >= -1 && index < static_cast<std::int64_t>(images.size());
  };
  for (const Material& material : materials) {
    if (!image_ok(material.base_colour_image) || !image_ok(material.normal_image)) {
      return fail("material '" + material.name + "' names an image that does not exist");
    }
  }
  for (std::size_t i = 0; i < images.size(); ++i) {
    const EncodedImage& image = images[i];
    if (image.name.empty() || image.name.find_first_of("/\\") != std::string::npos) {
      return fail("image " + std::to_string(i) + " has no plain file name");
    }
    if (image.width == 0 || image.height == 0 || image.bytes.empty()) {
      return fail("image '" + image.name + "' is empty");
    }
  }
  return true;
}

}  // namespace facerig
