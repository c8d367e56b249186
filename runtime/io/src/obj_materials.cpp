#include "obj_materials.h"

#include <sys/stat.h>

#include <cerrno>
#include <map>
#include <set>
#include <string_view>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/image_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/mtl.h"

namespace facerig {
namespace {

bool IsMissing(const std::filesystem::path& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) != 0 && errno == ENOENT;
}

class ObjMaterialReader {
 public:
  ObjMaterialReader(const std::filesystem::path& obj_path, Mesh* mesh, std::vector<std::string>* warnings)
      : obj_path_(obj_path), mesh_(*mesh), warnings_(*warnings) {
    std::error_code error;
    obj_folder_ = std::filesystem::weakly_canonical(std::filesystem::absolute(obj_path, error).parent_path(), error);
    if (error) throw IoError(IoErrorKind::kOpenFailed, obj_path.string(), "its folder cannot be resolved: " + error.message());
  }

  void ReadLibrary(const std::string& name) {
    const std::filesystem::path path = ResolveInsideFolder(obj_path_, name, "mtllib");
    for (const Library& library : libraries_) {
      if (library.path == path) return;
    }
    if (IsMissing(path)) {
      warnings_.push_back("mtllib '" + QuoteInput(name) + "' does not exist; its materials stay default");
      return;
    }
    const std::string text = ReadInputText(path, kMaxMtlFileBytes);
    libraries_.push_back({path, ParseMtl(text, path.string())});
  }

  // Each material the mesh names takes the first definition of its name.
  void FillMaterials() {
    for (Material& material : mesh_.materials) {
      const auto [library, found] = Find(material.name);
      if (found == nullptr) {
        // "default" is the reader's (and writer's) name for faces without usemtl.
        if (material.name != "default") {
          warnings_.push_back("material '" + QuoteInput(material.name) + "' is in no mtllib file");
        }
        continue;
      }
      const std::string name = std::move(material.name);
      material = found->material;
      material.name = name;
      material.base_colour_image = ReadImage(library->path, found->base_colour_map);
      material.normal_image = ReadImage(library->path, found->normal_map);
    }
  }

 private:
  struct Library {
    std::filesystem::path path;
    std::vector<MtlMaterial> materials;
  };

  std::pair<const Library*, const MtlMaterial*> Find(const std::string& name) const {
    for (const Library& library : libraries_) {
      for (const MtlMaterial& material : library.materials) {
        if (material.material.name == name) return {&library, &material};
      }
    }
    return {nullptr, nullptr};
  }

  // The index in mesh->images of the map's file, read once per file; -1 for
  // no map or a missing file.
  std::int32_t ReadImage(const std::filesystem::path& mtl_path, const MtlMap& map) {
    if (map.file.empty()) return -1;
    auto refuse = [&](const IoError& error) -> std::int32_t {
      throw IoError(error.kind(), mtl_path.string(),
                    map.statement + ": '" + QuoteInput(map.file) + "': " + error.message(), map.line);
    };
    std::filesystem::path path;
    try {
      path = ResolveInsideFolder(mtl_path, map.file, map.statement);
    } catch (const IoError& error) {
      throw IoError(error.kind(), error.path(), error.message(), map.line);
    }
    if (!IsInsideFolder(path, obj_folder_)) {
      return refuse(IoError(IoErrorKind::kOpenFailed, "", "leads outside the OBJ's folder"));
    }
    if (const auto known = images_.find(path); known != images_.end()) return known->second;
    if (IsMissing(path)) {
      warnings_.push_back(mtl_path.filename().string() + ": " + map.statement + " '" + QuoteInput(map.file) +
                          "' does not exist; the material keeps its colour");
      return -1;
    }
    try {
      mesh_.images.push_back(ReadImageFile(path));
    } catch (const IoError& error) {
      return refuse(error);
    }
    const auto index = static_cast<std::int32_t>(mesh_.images.size() - 1);
    images_.emplace(path, index);
    return index;
  }

  const std::filesystem::path& obj_path_;
  std::filesystem::path obj_folder_;
  Mesh& mesh_;
  std::vector<std::string>& warnings_;
  std::vector<Library> libraries_;
  std::map<std::filesystem::path, std::int32_t> images_;
};

}  // namespace

void ReadObjMaterials(const std::filesystem::path& obj_path, std::span<const std::string> mtl_files, Mesh* mesh,
                      std::vector<std::string>* warnings) {
  if (mtl_files.empty()) return;
  ObjMaterialReader reader(obj_path, mesh, warnings);
  std::set<std::string_view> seen;  // a file named on every line is read once
  for (const std::string& name : mtl_files) {
    if (seen.insert(name).second) reader.ReadLibrary(name);
  }
  reader.FillMaterials();
}

}  // namespace facerig
