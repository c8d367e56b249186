// A baked photo texture put on a mesh's skin parts.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "facerig/offline/photo/texture.h"
#include "facerig/runtime/part_roles.h"
#include "photo/texture/internal.h"

namespace facerig {
namespace {

// An image name the mesh does not use yet.
std::string UnusedImageName(const Mesh& mesh, const std::string& wanted) {
  const auto used = [&](const std::string& name) {
    return std::any_of(mesh.images.begin(), mesh.images.end(), [&](const EncodedImage& i) { return i.name == name; });
  };
  const std::string stem = wanted.substr(0, wanted.rfind('.')), extension = wanted.substr(wanted.rfind('.'));
  std::string name = wanted;
  for (int n = 2; used(name); ++n) name = stem + "_" + std::to_string(n) + extension;
  return name;
}

// Drops the materials no triangle uses and the images no material uses.
void DropUnused(Mesh& mesh) {
  std::vector<std::int64_t> material_to(mesh.materials.size(), -1);
  std::vector<Material> materials;
  for (std::uint32_t& m : mesh.triangle_materials) {
    if (material_to[m] < 0) material_to[m] = static_cast<std::int64_t>(materials.size()), materials.push_back(mesh.materials[m]);
    m = static_cast<std::uint32_t>(material_to[m]);
  }
  std::vector<std::int64_t> image_to(mesh.images.size(), -1);
  std::vector<EncodedImage> images;
  for (Material& material : materials) {
    for (std::int32_t* index : {&material.base_colour_image, &material.normal_image}) {
      if (*index < 0) continue;
      const auto i = static_cast<std::size_t>(*index);
      if (image_to[i] < 0) image_to[i] = static_cast<std::int64_t>(images.size()), images.push_back(std::move(mesh.images[i]));
      *index = static_cast<std::int32_t>(image_to[i]);
    }
  }
  mesh.materials = std::move(materials);
  mesh.images = std::move(images);
}

// Appends the image and a material textured by it; the material's index.
std::uint32_t AddTexturedMaterial(Mesh& mesh, Material material, EncodedImage image) {
  image.name = UnusedImageName(mesh, image.name);
  mesh.images.push_back(std::move(image));
  material.base_colour_image = static_cast<std::int32_t>(mesh.images.size() - 1);
  mesh.materials.push_back(std::move(material));
  return static_cast<std::uint32_t>(mesh.materials.size() - 1);
}

}  // namespace

void ApplyPhotoTexture(Mesh& mesh, const PhotoTexture& texture) {
  if (mesh.triangle_materials.empty()) ReplacePlaceholderMaterials(mesh);
  const std::uint32_t photo = AddTexturedMaterial(mesh, texture.material, texture.image);
  std::vector<std::pair<glm::ivec2, std::uint32_t>> tiles;
  for (const PhotoTextureTile& tile : texture.other_tiles) {
    Material material = texture.material;
    material.name = tile.image.name.substr(0, tile.image.name.rfind('.'));  // "photo_skin_<u>_<v>"
    tiles.emplace_back(tile.tile, AddTexturedMaterial(mesh, material, tile.image));
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const bool skin = mesh.triangle_parts.empty() || RoleOfPart(mesh.part_names[mesh.triangle_parts[t]]) == PartRole::kSkin;
    if (!skin) continue;
    mesh.triangle_materials[t] = photo;
    if (tiles.empty() || mesh.corner_uvs.empty()) continue;
    const glm::ivec2 tile = photo_texture::UvTile(mesh, t);
    for (const auto& [other, material] : tiles) mesh.triangle_materials[t] = other == tile ? material : mesh.triangle_materials[t];
  }
  DropUnused(mesh);
}

}  // namespace facerig
