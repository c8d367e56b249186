#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/io/rig_file.h"

#include <algorithm>
#include <cctype>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/rig_surface.h"

namespace facerig {
namespace {


}  // namespace

Rig RigFromObjMesh(const Mesh& mesh, const std::filesystem::path& path, const ObjLoadOptions& obj_options) {
  RawRig raw = ToRawRig(mesh);
  raw.units = obj_options.units;
  raw.up_axis = obj_options.up_axis;
  // A file that leaves some vertex without a normal gets all normals
  // recomputed: mixing given and computed normals would show seams.
  if (std::any_of(raw.normals.begin(), raw.normals.end(), [](const glm::vec3& n) { return n == glm::vec3(0.0f); })) {
    raw.normals.clear();
  }
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) throw IoError(IoErrorKind::kInvalidRig, path.string(), problem);
  return std::move(*rig);
}

Rig LoadRig(const std::filesystem::path& path, const ObjLoadOptions& obj_options) {
  const std::string ext = LowerExtension(path);
  if (ext == ".frig") return ReadFrig(path);
  if (ext == ".glb" || ext == ".gltf") return ReadGltf(path);
  if (ext == ".obj") {
    const Mesh mesh = ReadObj(path);
    std::string problem;
    std::optional<Rig> dressed = RigWithSurface(RigFromObjMesh(mesh, path, obj_options), GroupedByPart(mesh), &problem);
    if (!dressed) throw IoError(IoErrorKind::kInvalidRig, path.string(), problem);
    return std::move(*dressed);
  }
  throw IoError(IoErrorKind::kUnsupportedFormat, path.string(),
                "unknown extension '" + ext + "' (expected .obj, .glb, .gltf or .frig)");
}

void SaveRig(const std::filesystem::path& path, const Rig& rig) {
  const std::string ext = LowerExtension(path);
  if (ext == ".frig") return WriteFrig(path, rig);
  if (ext == ".glb" || ext == ".gltf") return WriteGltf(path, rig);
  if (ext == ".obj") return WriteObj(path, rig);
  throw IoError(IoErrorKind::kUnsupportedFormat, path.string(),
                "unknown extension '" + ext + "' (expected .obj, .glb, .gltf or .frig)");
}

}  // namespace facerig
