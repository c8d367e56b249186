// The linear face model a photo is fitted with: the template's neutral,
// identity modes (identity mesh - neutral) and a few of its expressions.
#include <algorithm>
#include <limits>
#include <string>
#include <system_error>

#include <glm/geometric.hpp>

#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_builder.h"
#include "geometry/bounding_box.h"

namespace facerig {

namespace {

std::vector<glm::vec3> DenseDeltas(const Rig& rig, std::size_t shape) {
  std::vector<glm::vec3> dense(rig.vertex_count(), glm::vec3(0.0f));
  const BlendShapeView view = rig.shape(shape);
  for (std::size_t i = 0; i < view.vertex_indices.size(); ++i) dense[view.vertex_indices[i]] = view.position_deltas[i];
  return dense;
}

// The lower face between the chin and the level of the jaw line's top points
// (dlib 0 and 16), measured along the face's own up axis (chin -> brows), so
// the template may lie in any orientation.
std::vector<std::uint32_t> ContourCandidates(std::span<const glm::vec3> neutral, VertexRange face,
                                             std::span<const std::uint32_t> landmarks) {
  const glm::vec3 chin = neutral[landmarks[dlib68::kChin]];
  const glm::vec3 brows = 0.5f * (neutral[landmarks[dlib68::kRightBrowPeak]] + neutral[landmarks[dlib68::kLeftBrowPeak]]);
  const glm::vec3 up = glm::normalize(brows - chin);
  const float top = std::max(glm::dot(neutral[landmarks[dlib68::kJawFirst]] - chin, up),
                             glm::dot(neutral[landmarks[dlib68::kJawLast]] - chin, up));
  const float bottom = -0.15f * glm::length(brows - chin);
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t v = face.first; v <= face.last && v < neutral.size(); ++v) {
    const float height = glm::dot(neutral[v] - chin, up);
    if (height >= bottom && height <= top) candidates.push_back(v);
  }
  return candidates;
}

std::vector<Triangle> RegionTriangles(std::span<const Triangle> triangles, VertexRange region) {
  std::vector<Triangle> inside;
  for (const Triangle& t : triangles) {
    if (t[0] <= region.last && t[1] <= region.last && t[2] <= region.last) inside.push_back(t);
  }
  return inside;
}

// The colours a photo shows each part in, for the detector's renders: dlib
// places the lids, brows and lips differently on a grey or all-skin render
// than on skin with white eyes, dark lashes and a dark mouth. Eyeballs and
// sockets go by their names where the part roles do not say.
glm::vec3 DetectorColour(const std::string& part_name) {
  if (part_name.find("eyeball") != std::string::npos) return {0.85f, 0.85f, 0.82f};
  if (part_name.find("socket") != std::string::npos) return {0.45f, 0.20f, 0.20f};
  switch (RoleOfPart(part_name)) {
    case PartRole::kSclera: return {0.85f, 0.85f, 0.82f};
    case PartRole::kIris: return {0.30f, 0.22f, 0.15f};
    case PartRole::kPupil: return {0.03f, 0.03f, 0.03f};
    case PartRole::kLashes: return {0.15f, 0.10f, 0.08f};
    case PartRole::kTeeth: return {0.90f, 0.90f, 0.85f};
    case PartRole::kGums:
    case PartRole::kTongue:
    case PartRole::kMouthInner: return {0.45f, 0.20f, 0.20f};
    case PartRole::kSkin:
    case PartRole::kEyeLayer: break;
  }
  return {0.86f, 0.66f, 0.55f};
}

// The neutral as a photo would show it: every part but the transparent layers
// (ICT-FaceKit's eye occlusion, tear film and blend meshes would hide the eyes
// in an opaque render), and each triangle's colour.
Mesh VisibleNeutral(const Rig& rig, const FaceTemplateInfo& info, std::vector<glm::vec3>& albedo) {
  Mesh mesh{.positions = {rig.positions().begin(), rig.positions().end()}};
  albedo.clear();
  for (const Triangle& t : rig.triangles()) {
    const auto part = std::find_if(info.parts.begin(), info.parts.end(), [&](const TemplatePart& p) {
      return t[0] >= p.vertices.first && t[0] <= p.vertices.last;
    });
    const std::string name = part == info.parts.end() ? std::string() : part->name;
    if (RoleOfPart(name) == PartRole::kEyeLayer) continue;
    mesh.triangles.push_back(t);
    albedo.push_back(DetectorColour(name));
  }
  return mesh;
}

constexpr int kCalibrationImageSize = 512;

}  // namespace

std::vector<glm::vec2> MeasureDlibOffsets(const PhotoFaceModel& model, std::span<const glm::vec3> positions,
                                          RasterView view, LandmarkDetector& detector) {
  Mesh mesh{.positions = {positions.begin(), positions.end()}, .triangles = model.visible_triangles};
  std::vector<glm::vec3> normals(mesh.positions.size());
  ComputeVertexNormals(mesh.positions, mesh.triangles, normals);
  for (const Triangle& t : mesh.triangles) {
    for (const std::uint32_t v : t) mesh.corner_normals.push_back(normals[v]);
  }
  const RgbImage photo = Shade(Rasterize(mesh, view), mesh, model.visible_albedo, view);
  const std::vector<glm::vec2> detected = DetectPhotoLandmarks(detector, photo).pixels;
  const glm::vec2 extent = BoxAround(std::span<const glm::vec2>(detected)).extent();
  const float size = std::max(1.0f, std::max(extent.x, extent.y));
  std::vector<glm::vec2> offsets(kDlibLandmarkCount, glm::vec2(0.0f));
  for (std::size_t k = 0; k < kDlibLandmarkCount; ++k) {
    if (k < 17 && (k < 7 || k > 9)) continue;
    const glm::vec2 vertex(ProjectToImage(view, mesh.positions[model.landmark_vertices[k]]));
    offsets[k] = (vertex - detected[k]) / size;
  }
  return offsets;
}

namespace {

// Where dlib puts each landmark on a render of the neutral from the front.
std::vector<glm::vec2> NeutralOffsets(const Rig& rig, const FaceTemplateInfo& info, const PhotoFaceModel& model,
                                      LandmarkDetector& detector) {
  std::vector<glm::vec3> albedo;
  Mesh mesh = VisibleNeutral(rig, info, albedo);
  RasterView view = detector.Detect(mesh).view;  // the front view, the face filling half of it
  view.width = kCalibrationImageSize;
  view.height = kCalibrationImageSize;
  return MeasureDlibOffsets(model, model.neutral, view, detector);
}

}  // namespace

PhotoFaceModel BuildPhotoFaceModel(const Rig& rig, const FaceTemplateInfo& info,
                                   std::span<const std::vector<glm::vec3>> identities,
                                   const PhotoModelParams& params, LandmarkDetector* detector) {
  if (info.landmark_vertices.size() != kDlibLandmarkCount) {
    throw InvalidInputError("photo model: the template descriptor has no 68 landmark vertices", "landmarks");
  }
  PhotoFaceModel model;
  model.neutral.assign(rig.positions().begin(), rig.positions().end());
  for (std::size_t i = 0; i < identities.size(); ++i) {
    if (identities[i].size() != model.neutral.size()) {
      throw InvalidInputError("photo model: identity mesh " + std::to_string(i) + " has " +
                                  std::to_string(identities[i].size()) + " vertices, the template " +
                                  std::to_string(model.neutral.size()),
                              "identity", std::to_string(i));
    }
    std::vector<glm::vec3> mode(model.neutral.size());
    for (std::size_t v = 0; v < mode.size(); ++v) mode[v] = identities[i][v] - model.neutral[v];
    model.identity_modes.push_back(std::move(mode));
  }
  for (const std::string& name : params.expressions) {
    const std::optional<std::size_t> shape = rig.FindShape(name);
    if (!shape) continue;
    model.expression_names.push_back(name);
    model.expression_deltas.push_back(DenseDeltas(rig, *shape));
  }
  model.landmark_vertices = info.landmark_vertices;
  model.region = info.region;
  model.contour_candidates = ContourCandidates(model.neutral, info.Group("face"), model.landmark_vertices);
  model.region_triangles = RegionTriangles(rig.triangles(), info.region);
  model.visible_triangles = VisibleNeutral(rig, info, model.visible_albedo).triangles;
  model.detector = detector;
  model.landmark_offsets = detector != nullptr ? NeutralOffsets(rig, info, model, *detector)
                                               : std::vector<glm::vec2>(kDlibLandmarkCount, glm::vec2(0.0f));
  return model;
}

std::vector<std::vector<glm::vec3>> LoadIdentityMeshes(const std::filesystem::path& folder, std::size_t vertex_count,
                                                       std::size_t max_count) {
  std::vector<std::vector<glm::vec3>> identities;
  for (std::size_t i = 0; i < max_count; ++i) {
    std::string number = std::to_string(i);
    if (number.size() < 3) number.insert(0, 3 - number.size(), '0');
    const std::filesystem::path path = folder / ("identity" + number + ".obj");
    std::error_code error;
    if (!std::filesystem::exists(path, error)) break;
    Mesh mesh = ReadObj(path);
    if (mesh.positions.size() != vertex_count) {
      throw InvalidInputError("photo model: " + path.string() + " has " + std::to_string(mesh.positions.size()) +
                                  " vertices, the template " + std::to_string(vertex_count),
                              path.string());
    }
    identities.push_back(std::move(mesh.positions));
  }
  return identities;
}

}  // namespace facerig
