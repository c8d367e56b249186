// Finding a template's descriptor (explicit, beside the rig, shipped by
// fingerprint) or deriving one from the mesh (face_template.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/rig_file.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// Parts as contiguous vertex ranges: the rig's part groups when it has
// several, else its connected components when each is contiguous, else one.
std::vector<TemplatePart> DeriveParts(const Rig& rig) {
  std::vector<TemplatePart> parts;
  for (const Part& part : rig.parts()) {
    if (part.vertex_count == 0) continue;
    parts.push_back({part.name, {part.first_vertex, part.first_vertex + part.vertex_count - 1}});
  }
  if (parts.size() > 1) return parts;
  parts.clear();
  std::vector<std::uint32_t> component_of;
  const std::size_t components = ConnectedComponents(rig.vertex_count(), rig.triangles(), component_of);
  std::uint32_t start = 0;
  for (std::uint32_t v = 1; v <= component_of.size(); ++v) {
    if (v == component_of.size() || component_of[v] != component_of[start]) {
      parts.push_back({"component" + std::to_string(parts.size()), {start, v - 1}});
      start = v;
    }
  }
  if (parts.size() != components) parts = {{"all", {0, static_cast<std::uint32_t>(rig.vertex_count() - 1)}}};
  return parts;
}

// The nearest region vertex to each detected landmark point.
std::vector<std::uint32_t> DetectLandmarkVertices(const Rig& rig, VertexRange region, LandmarkDetector& detector) {
  const LandmarkResult detected = detector.Detect(NeutralMesh(rig));
  std::vector<std::uint32_t> vertex_of(kDlibLandmarkCount, 0);
  for (std::size_t i = 0; i < detected.landmarks.points.size(); ++i) {
    float best = std::numeric_limits<float>::infinity();
    std::uint32_t best_vertex = 0;
    for (std::uint32_t v = region.first; v <= region.last; ++v) {
      const float d = glm::length(rig.positions()[v] - detected.landmarks.points[i]);
      if (d < best) {
        best = d;
        best_vertex = v;
      }
    }
    vertex_of[detected.landmarks.indices[i]] = best_vertex;
  }
  return vertex_of;
}

std::optional<FaceTemplateInfo> ShippedMatch(const Rig& rig, const std::vector<fs::path>& dirs) {
  const TemplateFingerprint print = FingerprintOf(rig);
  const std::string checksum = "\"" + print.neutral_checksum + "\"";
  for (const fs::path& dir : dirs) {
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
      const std::string name = entry.path().filename().string();
      if (!name.ends_with(".template.json")) continue;
      std::string text;
      try {
        text = ReadInputText(entry.path(), kMaxTemplateDescriptorBytes);
      } catch (const IoError&) {
        continue;  // unreadable, not a regular file or too large: not a descriptor to match
      }
      // Cheap pre-filter; the full parse checks the whole fingerprint.
      if (text.find(checksum) == std::string::npos) continue;
      return ParseFaceTemplateInfo(text, rig, entry.path().string());
    }
  }
  return std::nullopt;
}

}  // namespace

FaceTemplateInfo DeriveFaceTemplateInfo(const Rig& rig, LandmarkDetector* detector) {
  FaceTemplateInfo info;
  info.name = "derived";
  info.fingerprint = FingerprintOf(rig);
  info.parts = DeriveParts(rig);
  const auto all = static_cast<std::uint32_t>(rig.vertex_count() - 1);
  // The skin comes first in an artist's or the built-in head's vertex order:
  // the first part group, or the largest component when it starts at vertex 0.
  info.region = {0, all};
  if (rig.parts().size() > 1 && info.parts.size() > 1 && info.parts[0].vertices.first == 0) {
    info.region = info.parts[0].vertices;
  } else if (info.parts.size() > 1) {
    const auto largest = std::max_element(info.parts.begin(), info.parts.end(), [](const auto& a, const auto& b) {
      return a.vertices.count() < b.vertices.count();
    });
    if (largest->vertices.first == 0) info.region = largest->vertices;
  }
  info.vertex_groups["face"] = info.region;
  info.derived = {"parts", "region", "rims", "vertex_groups"};
  if (detector) {
    info.landmark_vertices = DetectLandmarkVertices(rig, info.region, *detector);
    info.derived.push_back("landmarks");
  }
  return info;
}

std::vector<fs::path> ShippedTemplateDirectories() {
  std::vector<fs::path> dirs;
  std::error_code error;
#ifdef FACERIG_SOURCE_TEMPLATES_DIR
  if (fs::is_directory(FACERIG_SOURCE_TEMPLATES_DIR, error)) dirs.emplace_back(FACERIG_SOURCE_TEMPLATES_DIR);
#endif
#ifdef FACERIG_INSTALLED_TEMPLATES_DIR
  if (fs::is_directory(FACERIG_INSTALLED_TEMPLATES_DIR, error)) dirs.emplace_back(FACERIG_INSTALLED_TEMPLATES_DIR);
#endif
  // An install moved to another prefix: <prefix>/bin/facerig -> <prefix>/share/facerig/templates.
  const fs::path beside_program = fs::read_symlink("/proc/self/exe", error).parent_path().parent_path() /
                                  "share" / "facerig" / "templates";
  if (!error && fs::is_directory(beside_program, error) &&
      std::find(dirs.begin(), dirs.end(), beside_program) == dirs.end()) {
    dirs.push_back(beside_program);
  }
  return dirs;
}

FaceTemplateInfo ResolveFaceTemplateInfo(const Rig& rig, const fs::path& rig_path, const fs::path& explicit_path,
                                         const std::vector<fs::path>& shipped_dirs) {
  if (!explicit_path.empty()) {
    FaceTemplateInfo info = LoadFaceTemplateInfo(explicit_path, rig);
    info.source = TemplateInfoSource::kExplicit;
    return info;
  }
  std::error_code error;
  const fs::path beside = fs::is_directory(rig_path, error)
                              ? rig_path / "template.json"
                              : fs::path(rig_path).replace_extension(".template.json");
  if (!rig_path.empty() && fs::is_regular_file(beside, error)) {
    FaceTemplateInfo info = LoadFaceTemplateInfo(beside, rig);
    info.source = TemplateInfoSource::kBesideRig;
    return info;
  }
  if (std::optional<FaceTemplateInfo> shipped = ShippedMatch(rig, shipped_dirs)) {
    shipped->source = TemplateInfoSource::kShipped;
    return *shipped;
  }
  return DeriveFaceTemplateInfo(rig);
}

FaceTemplate LoadFaceTemplate(const fs::path& rig_path, const fs::path& explicit_info) {
  Rig rig = LoadRigOrTemplateFolder(rig_path);
  FaceTemplateInfo info = ResolveFaceTemplateInfo(rig, rig_path, explicit_info);
  return {std::move(rig), std::move(info)};
}

std::vector<std::uint32_t> TemplateLandmarkVertices(const Rig& rig, FaceTemplateInfo& info,
                                                    LandmarkDetector& detector) {
  if (info.landmark_vertices.empty()) {
    info.landmark_vertices = DetectLandmarkVertices(rig, info.region, detector);
    info.derived.push_back("landmarks");
  }
  return info.landmark_vertices;
}

std::optional<FaceLandmarks> LandmarksOnTemplateTopology(const Rig& template_rig, const FaceTemplateInfo& info,
                                                         std::span<const glm::vec3> target_positions,
                                                         std::span<const Triangle> target_triangles) {
  if (info.landmark_vertices.size() != kDlibLandmarkCount || target_positions.size() != template_rig.vertex_count() ||
      !std::equal(target_triangles.begin(), target_triangles.end(), template_rig.triangles().begin(),
                  template_rig.triangles().end())) {
    return std::nullopt;
  }
  FaceLandmarks landmarks;
  for (std::uint32_t i = 0; i < kDlibLandmarkCount; ++i) {
    landmarks.points.push_back(target_positions[info.landmark_vertices[i]]);
    landmarks.indices.push_back(i);
    landmarks.confidence.push_back(1.0f);
  }
  return landmarks;
}

}  // namespace facerig
