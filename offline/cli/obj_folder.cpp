#include "cli/obj_folder.h"

#include <algorithm>
#include <cctype>
#include <future>
#include <thread>
#include <vector>

#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/io/obj.h"

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

namespace {

// The shapes s = first, first + stride, ... each as an OBJ of the shaped
// face: positions and UVs, as ICT-FaceKit's expression OBJs (a reader makes
// the normals; they were a third of the bytes, and writing is what takes the
// time).
void WriteShapeObjs(const std::filesystem::path& folder, const Rig& rig, const ObjTopologyWriter& writer,
                    std::size_t first, std::size_t stride) {
  std::vector<glm::vec3> positions;
  for (std::size_t s = first; s < rig.shape_count(); s += stride) {
    positions.assign(rig.positions().begin(), rig.positions().end());
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      positions[shape.vertex_indices[i]] += shape.position_deltas[i];
    }
    writer.Write(folder / ShapeFileName(shape.name), positions, {}, rig.uvs());
    ThrowIfStopped();
  }
}

}  // namespace

void WriteRigObjFolder(const std::filesystem::path& folder, const Rig& rig) {
  const MtlReference mtl = rig.materials().empty()
                               ? MtlReference{}
                               : WriteMtl(folder, "materials.mtl", rig.materials(), rig.images());
  // Every OBJ of the folder has the rig's faces: formatted once for the
  // neutral (with its normals) and once for the shapes.
  const ObjTopologyWriter neutral(rig.triangles(), rig.parts(), mtl, !rig.normals().empty(), !rig.uvs().empty(),
                                  (folder / "neutral.obj").string());
  neutral.Write(folder / "neutral.obj", rig.positions(), rig.normals(), rig.uvs());
  CheckAfterWrite("obj-neutral", folder / "neutral.obj");
  const ObjTopologyWriter writer(rig.triangles(), rig.parts(), mtl, false, !rig.uvs().empty(),
                                 (folder / "neutral.obj").string());
  // Shapes are independent files: one worker per core (formatting, not the
  // disk, takes the time).
  const std::size_t workers = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
  std::vector<std::future<void>> running;
  for (std::size_t w = 1; w < workers; ++w) {
    running.push_back(std::async(std::launch::async, WriteShapeObjs, std::cref(folder), std::cref(rig), std::cref(writer), w, workers));
  }
  std::exception_ptr failure;
  try {
    WriteShapeObjs(folder, rig, writer, 0, workers);
  } catch (...) {
    failure = std::current_exception();
  }
  // Every worker finishes before the folder goes; the first failure is thrown.
  for (std::future<void>& worker : running) {
    try {
      worker.get();
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

std::filesystem::path AddObjFolderOutput(OutputSet& set, const std::string& path, const char* option) {
  const ReplaceableFolder obj_folder{[](const std::filesystem::path& name) {
                                       const std::string extension = name.extension().string();
                                       return extension == ".obj" || extension == ".mtl" || extension == ".png" ||
                                              extension == ".jpg";
                                     },
                                     ".obj, .mtl, .png and .jpg files", option};
  return set.Add(path, OutputSet::Kind::kFolder, obj_folder);
}

}  // namespace facerig::cli
