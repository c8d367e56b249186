// A skinned character as an artist's exporter writes it, around given
// geometry: three joints in a node hierarchy with non-identity transforms,
// inverse bind matrices, JOINTS_0/WEIGHTS_0, COLOR_0 and TEXCOORD_1 besides
// the usual attributes, a textured material with an extension, and a small
// animation of the joints. Written by hand (JSON + buffer) so that it does not
// depend on the library under test.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::test {

// One primitive's own vertices (normals and uvs empty or one per vertex).
struct SkinnedPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;  // glTF's convention (V down); made up when empty
  std::vector<Triangle> triangles;
};

struct SkinnedGltfOptions {
  // .gltf: the buffer and the texture as data URIs; .glb: in the BIN chunk.
  // An extra LINES primitive on the first primitive's vertices when asked.
  bool with_lines = false;
};

// Writes `primitives` as one skinned mesh (one primitive each, in order).
void WriteSkinnedGltf(const std::filesystem::path& path, const std::vector<SkinnedPrimitive>& primitives,
                      const SkinnedGltfOptions& options = {});

// A .glb or .gltf as JSON and the bytes of each buffer (BIN chunk or data URI).
struct GltfFile {
  nlohmann::json document;
  std::vector<std::vector<unsigned char>> buffers;
};
GltfFile ReadGltfFile(const std::filesystem::path& path);

// The elements of an accessor with a bufferView, packed (no stride).
std::vector<unsigned char> AccessorBytes(const GltfFile& file, int accessor);
// The bytes of an image stored in a bufferView.
std::vector<unsigned char> ImageBytes(const GltfFile& file, int image);
// The 2x2 PNG the material's texture uses.
std::span<const unsigned char> TexturePng();

}  // namespace facerig::test
