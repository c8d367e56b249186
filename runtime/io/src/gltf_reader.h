// The glTF reader (ReadGltf, ParseGltf, ReadGltfMesh), shared by the files
// that implement it by topic: gltf_read.cpp (vertices, parts, the chosen
// mesh), gltf_read_shapes.cpp (morph targets), gltf_read_materials.cpp
// (materials and images), gltf_read_scene.cpp (every mesh of the scene) and
// gltf_read_weld.cpp (parts written on their own vertices, joined back).
// Private to facerig::runtime_io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "gltf_internal.h"
#include "facerig/runtime/material.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"
#include "gltf_accessors.h"
#include "gltf_scene.h"

namespace facerig::gltf_internal {

class GltfReader {
 public:
  GltfReader(std::string path, tinygltf::Model model, std::uint64_t file_size)
      : path_(std::move(path)), model_(std::move(model)), file_size_(file_size) {}

  // The rig, and the neutral as a Mesh into *mesh when not null.
  Rig Read(Mesh* mesh);
  Mesh ReadMesh();
  // Every mesh of the scene in scene space (SceneMerger), for files that are
  // not one of facerig's: nullopt when the scene is one untransformed mesh or
  // facerig's own (Read then reads it as it is).
  std::optional<Rig> ReadScene() const;

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message);
  }

  RawBlendShape ReadShape(const std::vector<VertexBlock>& blocks, std::size_t target, std::string name,
                          bool with_normals) const;
  void ReadVertices(const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadParts(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                 std::vector<std::size_t>* part_primitives) const;
  void ReadNeutral(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                   std::vector<std::size_t>* part_primitives) const;
  // Which rig vertex each vertex read from the blocks is (gltf_read_weld.cpp):
  // from facerig's extras.facerig.vertices; empty when the primitives have none.
  std::vector<std::uint32_t> ReadRigVertices(const MeshVertices& vertices) const;
  // Joins the vertices the blocks repeat, in the rig's order (`rig_vertex` not empty).
  void WeldNeutral(const std::vector<std::uint32_t>& rig_vertex, RawRig* raw) const;
  void WeldShapes(const std::vector<std::uint32_t>& rig_vertex, RawRig* raw) const;
  // The chosen mesh read up to its neutral (welded): what both Read and ReadMesh need.
  struct Neutral {
    int mesh_index = -1;
    const tinygltf::Mesh* mesh = nullptr;
    MeshVertices vertices;
    RawRig raw;
    std::vector<std::size_t> part_primitives;
    std::vector<std::uint32_t> rig_vertex;  // ReadRigVertices
  };
  Neutral ReadChosenNeutral() const;
  Mesh NeutralMeshOf(int mesh_index, const RawRig& raw, const std::vector<std::size_t>& part_primitives) const;
  std::vector<std::int32_t> ReadImages(Mesh* mesh) const;
  // The document's images and every material, in its order, into *mesh.
  void ReadMaterials(Mesh* mesh) const;
  std::int32_t ImageOfTexture(int texture_index, const std::vector<std::int32_t>& kept) const;
  Material ReadMaterial(const tinygltf::Material& material, const std::vector<std::int32_t>& kept) const;
  int MaterialOf(const tinygltf::Primitive& primitive) const;
  int ChosenMesh() const;
  void ReadShapes(const tinygltf::Mesh& mesh, const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadFrame(const tinygltf::Mesh& mesh, RawRig* raw) const;
  bool ReadsAsItIs(const MeshInstance& only, const std::vector<glm::dmat4>& node_worlds) const;
  RawRig ReadScenePiece(const MeshInstance& instance, const std::vector<glm::dmat4>& node_worlds,
                        std::int32_t default_material, bool* used_default) const;

  // A view of this reader's model and file (built per use: the reader may move).
  GltfAccessors Accessors() const { return GltfAccessors(path_, model_, file_size_); }

  std::string path_;
  tinygltf::Model model_;
  std::uint64_t file_size_;
};

// tinygltf's Value::Get(key) asserts that the value is an object; extras may be anything.
const tinygltf::Value& Member(const tinygltf::Value& object, const char* key);
// The string at `index` of `array`, else `fallback`.
std::string StringOr(const tinygltf::Value& array, std::size_t index, std::string fallback);
// A part name for primitive p of a mesh with `part_count` parts:
// extras.facerig.parts, else the mesh's (or node's) name `base`, with the
// primitive's material name (or "primitive<p>") when it has several parts.
std::string PartName(const tinygltf::Model& model, const tinygltf::Mesh& mesh, const std::string& base,
                     std::size_t p, std::size_t part_count);

}  // namespace facerig::gltf_internal
