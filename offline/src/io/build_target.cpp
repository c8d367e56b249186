#include "facerig/runtime/ascii_case.h"
#include "facerig/offline/io/build_target.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

BuildTarget LoadBuildTarget(const std::filesystem::path& path, Units units) {
  const std::string extension = LowerExtension(path);
  const bool file = !std::filesystem::is_directory(path);
  BuildTarget target;
  if (file && extension == ".obj") {
    const Mesh mesh = ReadObj(path);
    target.rig = RigBuilder::ToRaw(RigFromObjMesh(mesh, path, ObjLoadOptions{units, UpAxis::kY}));
    target.mesh = GroupedByPart(mesh);
  } else if (file && (extension == ".glb" || extension == ".gltf")) {
    target.rig = RigBuilder::ToRaw(ReadGltf(path, &target.mesh));
  } else {
    TemplateImportOptions options;
    options.units = units;
    target.rig = RigBuilder::ToRaw(LoadRigOrTemplateFolder(path, options));
    target.mesh = NeutralMesh(target.rig);
  }
  if (units != Units::kUnknown) target.rig.units = units;
  return target;
}

}  // namespace facerig
