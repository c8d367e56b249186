// The glTF reader's scenes: every mesh of the default scene as a viewer shows it.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gltf_reader.h"
#include "gltf_scene_skin.h"

namespace facerig::gltf_internal {

// Whether the scene is one mesh that ReadScene would leave as it is:
// facerig's own, or one that no node transform or skin moves.
bool GltfReader::ReadsAsItIs(const gltf_internal::MeshInstance& only,
                             const std::vector<glm::dmat4>& node_worlds) const {
  if (Member(model_.meshes[static_cast<std::size_t>(only.mesh)].extras, "facerig").IsObject()) return true;
  if (only.skin < 0) return only.world == glm::dmat4(1.0);
  return gltf_internal::SkinPose(model_, only.skin, node_worlds, path_, file_size_).LeavesMeshInPlace();
}

// One mesh of the scene in scene space, its parts named and with materials
// (`default_material` for those without one, noted in *used_default).
RawRig GltfReader::ReadScenePiece(const gltf_internal::MeshInstance& instance,
                                  const std::vector<glm::dmat4>& node_worlds, std::int32_t default_material,
                                  bool* used_default) const {
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(instance.mesh)];
  const std::string base = mesh.name.empty() ? model_.nodes[static_cast<std::size_t>(instance.node)].name : mesh.name;
  const MeshVertices vertices = GroupMeshVertices(model_, mesh, path_, file_size_);
  RawRig piece;
  std::vector<std::size_t> part_primitives;
  ReadNeutral(mesh, vertices, &piece, &part_primitives);
  ReadShapes(mesh, vertices.blocks, &piece);
  for (std::size_t i = 0; i < piece.parts.size(); ++i) {
    const std::size_t p = part_primitives[i];
    piece.parts[i].name = PartName(model_, mesh, base, p, piece.parts.size());
    const int material = MaterialOf(mesh.primitives[p]);
    piece.parts[i].material = material >= 0 ? material : default_material;
    *used_default = *used_default || material < 0;
  }
  if (instance.skin >= 0) {
    gltf_internal::SkinPose(model_, instance.skin, node_worlds, path_, file_size_).Apply(mesh, vertices, &piece);
  }
  const std::vector<std::uint32_t> rig_vertex = ReadRigVertices(vertices);
  if (!rig_vertex.empty()) {
    WeldNeutral(rig_vertex, &piece);
    WeldShapes(rig_vertex, &piece);
  }
  return piece;
}

std::optional<Rig> GltfReader::ReadScene() const {
  const std::vector<gltf_internal::MeshInstance> instances = gltf_internal::SceneMeshInstances(model_);
  if (instances.empty()) return std::nullopt;
  const std::vector<glm::dmat4> node_worlds = gltf_internal::NodeWorlds(model_);
  if (instances.size() == 1 && ReadsAsItIs(instances[0], node_worlds)) return std::nullopt;
  Mesh appearance;
  ReadMaterials(&appearance);
  std::vector<Material> materials = std::move(appearance.materials);
  const auto default_material = static_cast<std::int32_t>(materials.size());
  bool used_default = false;
  gltf_internal::SceneMerger merger;
  for (const gltf_internal::MeshInstance& instance : instances) {
    // A skinned piece is in scene space already: its node transform does not apply.
    merger.Add(ReadScenePiece(instance, node_worlds, default_material, &used_default), instance.world);
  }
  RawRig merged = merger.Finish();
  if (used_default) materials.push_back(Material{.name = "default"});
  merged.materials = std::move(materials);
  merged.images = std::move(appearance.images);
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(merged), &problem);
  if (!rig) Fail(IoErrorKind::kInvalidRig, problem);
  return rig;
}

}  // namespace facerig::gltf_internal
