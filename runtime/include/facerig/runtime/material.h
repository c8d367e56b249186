// Materials and the images they use, as a Mesh or a Rig carries them.
//
// Images stay encoded (PNG or JPEG bytes, as the file stored them): the
// runtime never decodes a pixel, a renderer does. Readers check each image's
// header (io/image_probe.h) before keeping it, so width and height are known.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

namespace facerig {

enum class AlphaMode : std::uint8_t { kOpaque = 0, kMask, kBlend };
enum class ImageFormat : std::uint8_t { kPng = 0, kJpeg };

const char* ToString(AlphaMode mode);
const char* MimeType(ImageFormat format);       // "image/png", "image/jpeg"
const char* FileExtension(ImageFormat format);  // ".png", ".jpg"

struct EncodedImage {
  std::string name{};  // a file name without folders, e.g. "skin.png"
  ImageFormat format = ImageFormat::kPng;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> bytes{};
};

// glTF 2.0's metallic-roughness subset that faces need.
struct Material {
  std::string name{};
  glm::vec4 base_colour{1.0f};  // linear RGBA
  // Indices into the owner's images; -1: none.
  std::int32_t base_colour_image = -1;
  std::int32_t normal_image = -1;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;  // kMask only
  bool double_sided = false;
  float roughness = 1.0f;  // glTF's default; lips and eyes are smoother
};

// Whether every image index of the materials is in range and every image has
// a name, a size and bytes; `problem` (if given) names the first offence.
bool ValidateMaterials(const std::vector<Material>& materials, const std::vector<EncodedImage>& images,
                       std::string* problem = nullptr);

}  // namespace facerig
