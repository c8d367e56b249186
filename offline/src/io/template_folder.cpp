#include "facerig/offline/io/template_folder.h"

#include <algorithm>
#include <exception>
#include <optional>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/offline/io/template_cache.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"
#include "geometry/parallel_for.h"
#include "geometry/bounding_box.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::string FindNeutral(const fs::path& folder, const TemplateImportOptions& options) {
  if (!options.neutral_file.empty()) return options.neutral_file;
  for (const char* candidate : {"generic_neutral_mesh.obj", "neutral.obj", "base.obj"}) {
    if (fs::exists(folder / candidate)) return candidate;
  }
  throw IoError(IoErrorKind::kOpenFailed, folder.string(),
                "no neutral mesh found (looked for generic_neutral_mesh.obj, neutral.obj, base.obj)");
}

// ICT-FaceKit lists its expressions in vertex_indices.json; the folder also
// holds identity meshes, which are not expressions.
std::vector<std::string> ShapeNamesFromJson(const fs::path& json_path) {
  const std::string text = ReadFileText(json_path, 64u << 20);
  CheckJsonNesting(text, json_path.string());
  nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) {
    throw IoError(IoErrorKind::kParse, json_path.string(), "not a JSON object");
  }
  const auto it = json.find("expressions");
  if (it == json.end() || !it->is_array()) {
    throw IoError(IoErrorKind::kParse, json_path.string(), "no \"expressions\" array");
  }
  std::vector<std::string> names;
  for (const auto& item : *it) {
    if (!item.is_string()) throw IoError(IoErrorKind::kParse, json_path.string(), "an expression name is not a string");
    names.push_back(item.get<std::string>());
  }
  return names;
}

std::vector<std::string> ShapeNames(const fs::path& folder, const std::string& neutral,
                                    const TemplateImportOptions& options) {
  if (!options.shape_names.empty()) return options.shape_names;
  // An explicit glob is the user's choice: it wins over vertex_indices.json.
  if (options.glob.empty() && fs::exists(folder / "vertex_indices.json")) {
    return ShapeNamesFromJson(folder / "vertex_indices.json");
  }
  const std::string glob = options.glob.empty() ? "*.obj" : options.glob;
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (!entry.is_regular_file() || file == neutral || !GlobMatch(glob, file)) continue;
    if (entry.path().extension() != ".obj") continue;
    names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// The expression meshes, parsed on all cores: each is independent. The first
// failure in name order is rethrown.
std::vector<Mesh> ReadExpressionMeshes(const fs::path& folder, const std::vector<std::string>& names) {
  std::vector<Mesh> meshes(names.size());
  std::vector<std::exception_ptr> errors(names.size());
  ParallelFor(names.size(), 1, [&](std::size_t i) {
    try {
      meshes[i] = ReadObj(folder / (names[i] + ".obj"));
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  return meshes;
}

float BoundingDiagonal(const std::vector<glm::vec3>& positions) {
  return BoxAround(std::span<const glm::vec3>(positions)).diagonal();
}

// An expression must be the neutral moved: same vertex count, same faces.
void CheckSameTopology(const Mesh& mesh, const fs::path& path, const Mesh& neutral, std::size_t vertex_count,
                       const std::string& neutral_name) {
  if (mesh.positions.size() != vertex_count) {
    throw IoError(IoErrorKind::kTopologyMismatch, path.string(),
                  std::to_string(mesh.positions.size()) + " vertices, the neutral " + neutral_name + " has " +
                      std::to_string(vertex_count));
  }
  if (mesh.triangles != neutral.triangles) {
    throw IoError(IoErrorKind::kTopologyMismatch, path.string(), "faces differ from the neutral " + neutral_name);
  }
}

// Sparse shapes from expression meshes on the neutral's vertices: position
// deltas, and area-weighted normal deltas when asked. The per-vertex buffers
// are reused from one expression to the next.
class ShapeDeltaMaker {
 public:
  ShapeDeltaMaker(const RawRig& neutral, bool with_normal_deltas)
      : neutral_(neutral), with_normal_deltas_(with_normal_deltas), deltas_(neutral.positions.size()) {
    if (!with_normal_deltas) return;
    neutral_normals_.resize(neutral.positions.size());
    shape_normals_.resize(neutral.positions.size());
    normal_deltas_.resize(neutral.positions.size());
    ComputeVertexNormals(neutral.positions, neutral.triangles, neutral_normals_);
  }

  // Empty without normal deltas.
  const std::vector<glm::vec3>& neutral_normals() const { return neutral_normals_; }

  // Counts the deltas at or under the report's drop threshold as it goes.
  RawBlendShape Make(const std::string& name, const Mesh& mesh, TemplateImportReport* report) {
    for (std::size_t v = 0; v < deltas_.size(); ++v) {
      deltas_[v] = mesh.positions[v] - neutral_.positions[v];
      const float length = glm::length(deltas_[v]);
      if (length > 0.0f && length <= report->drop_threshold) {
        ++report->dropped_entries;
        report->largest_dropped = std::max(report->largest_dropped, length);
      }
    }
    if (with_normal_deltas_) {
      ComputeVertexNormals(mesh.positions, neutral_.triangles, shape_normals_);
      for (std::size_t v = 0; v < normal_deltas_.size(); ++v) {
        normal_deltas_[v] = shape_normals_[v] - neutral_normals_[v];
      }
    }
    return MakeSparseShape(name, deltas_, normal_deltas_, report->drop_threshold);
  }

 private:
  const RawRig& neutral_;
  bool with_normal_deltas_;
  std::vector<glm::vec3> deltas_;
  std::vector<glm::vec3> neutral_normals_, shape_normals_, normal_deltas_;
};

}  // namespace

bool GlobMatch(std::string_view pattern, std::string_view name) {
  // Iterative matcher with backtracking to the last '*'.
  std::size_t p = 0, n = 0, star = std::string_view::npos, star_n = 0;
  while (n < name.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == name[n])) {
      ++p;
      ++n;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      star_n = n;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      n = ++star_n;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

Units GuessHeadUnits(float bounding_diagonal) {
  // A head (with or without neck) has a bounding-box diagonal of 0.1 - 1 m.
  if (bounding_diagonal >= 0.1f && bounding_diagonal <= 1.0f) return Units::kMetres;
  if (bounding_diagonal >= 10.0f && bounding_diagonal <= 100.0f) return Units::kCentimetres;
  if (bounding_diagonal >= 100.0f && bounding_diagonal <= 1000.0f) return Units::kMillimetres;
  return Units::kUnknown;
}

namespace {

// The import itself, without the cache.
Rig ImportFolder(const fs::path& folder, const TemplateImportOptions& options, TemplateImportReport* report) {
  const std::string neutral_name = FindNeutral(folder, options);
  const fs::path neutral_path = folder / neutral_name;
  const Mesh neutral = ReadObj(neutral_path);
  const std::vector<std::string> names = ShapeNames(folder, neutral_name, options);
  std::vector<Mesh> meshes = ReadExpressionMeshes(folder, names);

  const VertexAttributes neutral_attributes = PerVertexAttributes(neutral);
  RawRig raw = ToRawRig(neutral);
  raw.normals.clear();  // area-weighted, as the expressions' normal deltas
  raw.up_axis = options.up_axis;
  const float diagonal = BoundingDiagonal(raw.positions);
  raw.units = options.units != Units::kUnknown ? options.units : GuessHeadUnits(diagonal);

  TemplateImportReport local;
  local.neutral_path = neutral_path.string();
  local.drop_threshold = options.relative_drop_threshold * diagonal;
  local.units = raw.units;
  local.units_guessed = options.units == Units::kUnknown;
  local.uv_seam_vertices = neutral_attributes.uv_seam_vertices;

  ShapeDeltaMaker shape_deltas(raw, options.with_normal_deltas);
  if (options.with_normal_deltas) raw.normals = shape_deltas.neutral_normals();
  for (std::size_t i = 0; i < names.size(); ++i) {
    CheckSameTopology(meshes[i], folder / (names[i] + ".obj"), neutral, raw.positions.size(), neutral_name);
    raw.shapes.push_back(shape_deltas.Make(names[i], meshes[i], &local));
    local.kept_entries += raw.shapes.back().vertex_indices.size();
    meshes[i] = Mesh();  // release early: 53 meshes of ICT size are ~100 MB
  }

  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) throw IoError(IoErrorKind::kInvalidRig, folder.string(), problem);
  if (report) *report = local;
  return std::move(*rig);
}

}  // namespace

Rig ImportTemplateFolder(const fs::path& folder, const TemplateImportOptions& options,
                         TemplateImportReport* report) {
  if (!fs::is_directory(folder)) {
    throw IoError(IoErrorKind::kOpenFailed, folder.string(), "not a directory");
  }
  TemplateImportReport local;
  const std::optional<std::string> key =
      options.cache_folder.empty() ? std::nullopt : TemplateCacheKey(folder, options);
  if (key) {
    if (std::optional<Rig> cached = ReadCachedTemplate(options.cache_folder, *key, folder, &local)) {
      local.cache = TemplateCacheUse::kRead;
      if (report) *report = local;
      return std::move(*cached);
    }
  }
  Rig rig = ImportFolder(folder, options, &local);
  if (key) {
    try {
      StoreCachedTemplate(options.cache_folder, *key, folder, rig, local);
      local.cache = TemplateCacheUse::kStored;
    } catch (const std::exception& error) {  // the import stands; only the next run is slower
      local.cache = TemplateCacheUse::kNotStored;
      local.cache_problem = error.what();
    }
  }
  if (report) *report = local;
  return rig;
}

Rig LoadRigOrTemplateFolder(const fs::path& path, const TemplateImportOptions& options) {
  if (fs::is_directory(path)) return ImportTemplateFolder(path, options);
  return LoadRig(path, ObjLoadOptions{options.units, options.up_axis});
}

}  // namespace facerig
