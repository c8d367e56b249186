// The glTF reader's materials and the images they use.
#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/files/image_file.h"
#include "gltf_reader.h"

namespace facerig::gltf_internal {
namespace {

// A file name for image i: its uri's file name, else its name, else "image<i>",
// with the extension of its format.
std::string ImageFileName(const tinygltf::Image& image, std::size_t i, ImageFormat format) {
  std::string stem = image.uri.starts_with("data:") ? std::string() : image.uri;
  stem = stem.substr(stem.find_last_of("/\\") == std::string::npos ? 0 : stem.find_last_of("/\\") + 1);
  if (stem.empty()) stem = image.name;
  stem = stem.substr(0, stem.find_last_of('.'));
  std::erase_if(stem, [](char c) { return c == '/' || c == '\\' || c == '\0'; });
  if (stem.empty() || stem.size() > 100) stem = "image" + std::to_string(i);
  return stem + FileExtension(format);
}

}  // namespace

// The images that have bytes (embedded in a bufferView, a data URI, or an
// external file that exists), checked by their header. kept[i] is the index
// of image i in mesh->images, -1 when it has no bytes.
std::vector<std::int32_t> GltfReader::ReadImages(Mesh* mesh) const {
  std::vector<std::int32_t> kept;
  for (std::size_t i = 0; i < model_.images.size(); ++i) {
    const tinygltf::Image& image = model_.images[i];
    const std::string what = "images[" + std::to_string(i) + "]";
    std::span<const std::byte> bytes;
    if (image.bufferView >= 0) {
      bytes = Accessors().ViewBytes(image.bufferView, what);
    } else {
      bytes = {reinterpret_cast<const std::byte*>(image.image.data()), image.image.size()};
    }
    if (bytes.empty()) {
      kept.push_back(-1);  // a missing external file: the material keeps its colour
      continue;
    }
    kept.push_back(static_cast<std::int32_t>(mesh->images.size()));
    EncodedImage encoded = MakeEncodedImage(bytes, std::string(), path_ + ": " + what);  // probes the header
    encoded.name = ImageFileName(image, i, encoded.format);
    mesh->images.push_back(std::move(encoded));
  }
  return kept;
}

void GltfReader::ReadMaterials(Mesh* mesh) const {
  const std::vector<std::int32_t> kept = ReadImages(mesh);
  for (const tinygltf::Material& material : model_.materials) mesh->materials.push_back(ReadMaterial(material, kept));
}

std::int32_t GltfReader::ImageOfTexture(int texture_index, const std::vector<std::int32_t>& kept) const {
  if (texture_index < 0 || texture_index >= static_cast<int>(model_.textures.size())) return -1;
  const int source = model_.textures[static_cast<std::size_t>(texture_index)].source;
  return source >= 0 && source < static_cast<int>(kept.size()) ? kept[static_cast<std::size_t>(source)] : -1;
}

Material GltfReader::ReadMaterial(const tinygltf::Material& material, const std::vector<std::int32_t>& kept) const {
  Material read;
  read.name = material.name;
  const std::vector<double>& colour = material.pbrMetallicRoughness.baseColorFactor;
  if (colour.size() == 4 && std::all_of(colour.begin(), colour.end(), [](double c) { return std::isfinite(c); })) {
    for (int c = 0; c < 4; ++c) read.base_colour[c] = static_cast<float>(colour[static_cast<std::size_t>(c)]);
  }
  read.base_colour_image = ImageOfTexture(material.pbrMetallicRoughness.baseColorTexture.index, kept);
  read.normal_image = ImageOfTexture(material.normalTexture.index, kept);
  const double roughness = material.pbrMetallicRoughness.roughnessFactor;
  if (std::isfinite(roughness)) read.roughness = static_cast<float>(std::clamp(roughness, 0.0, 1.0));
  if (material.alphaMode == "MASK") read.alpha_mode = AlphaMode::kMask;
  if (material.alphaMode == "BLEND") read.alpha_mode = AlphaMode::kBlend;
  if (std::isfinite(material.alphaCutoff)) read.alpha_cutoff = static_cast<float>(material.alphaCutoff);
  read.double_sided = material.doubleSided;
  return read;
}

// The primitive's material; -1 for none, and for one that does not exist (the
// rig reader never required it to).
int GltfReader::MaterialOf(const tinygltf::Primitive& primitive) const {
  return primitive.material < static_cast<int>(model_.materials.size()) ? primitive.material : -1;
}

}  // namespace facerig::gltf_internal
