#include "cli_obj_folder.h"

#include <cctype>
#include <vector>

#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::cli {

std::string ShapeFileName(std::string_view name) {
  std::string file(name);
  for (char& c : file) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    if (!keep) c = '_';
  }
  if (file.empty() || file[0] == '.') file.insert(0, "shape_");
  return file + ".obj";
}

void WriteRigObjFolder(const std::filesystem::path& folder, const Rig& rig) {
  const MtlReference mtl = rig.materials().empty()
                               ? MtlReference{}
                               : WriteMtl(folder, "materials.mtl", rig.materials(), rig.images());
  WriteObj(folder / "neutral.obj", rig, mtl);
  CheckAfterWrite("obj-neutral", folder / "neutral.obj");
  std::vector<glm::vec3> positions, normals(rig.vertex_count());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    positions.assign(rig.positions().begin(), rig.positions().end());
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      positions[shape.vertex_indices[i]] += shape.position_deltas[i];
    }
    ComputeVertexNormals(positions, rig.triangles(), normals);
    WriteObj(folder / ShapeFileName(shape.name), positions, normals, rig.uvs(), rig.triangles(), rig.parts(), mtl);
    ThrowIfStopped();
  }
}

std::filesystem::path AddObjFolderOutput(OutputSet& set, const std::string& path) {
  const ReplaceableFolder obj_folder{[](const std::filesystem::path& name) {
                                       const std::string extension = name.extension().string();
                                       return extension == ".obj" || extension == ".mtl" || extension == ".png" ||
                                              extension == ".jpg";
                                     },
                                     ".obj, .mtl, .png and .jpg files", "--obj-dir"};
  return set.Add(path, OutputSet::Kind::kFolder, obj_folder);
}

}  // namespace facerig::cli
