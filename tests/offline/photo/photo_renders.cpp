#include "offline/photo/photo_renders.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/rig_builder.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig::test {
namespace {

glm::vec3 PartColour(const std::string& name) {
  if (name.starts_with("skin")) return {0.86f, 0.66f, 0.55f};
  if (name.starts_with("eyeball")) return {0.85f, 0.85f, 0.82f};
  if (name.starts_with("eyelashes")) return {0.15f, 0.10f, 0.08f};
  if (name == "teeth") return {0.9f, 0.9f, 0.85f};
  return {0.45f, 0.20f, 0.20f};  // mouth and eye sockets, gums
}

void AddNoise(RgbImage& image, float sigma) {
  Pcg32 rng(4242);
  for (std::uint8_t& v : image.pixels) {
    v = static_cast<std::uint8_t>(std::clamp(std::lround(v + 255.0 * sigma * rng.NextNormal()), 0L, 255L));
  }
}

// Smooth blotches in [-1, 1] over the head (cm): a few random plane waves.
float Blotches(glm::vec3 p) {
  static const std::vector<glm::vec4> waves = [] {
    Pcg32 rng(77);
    std::vector<glm::vec4> w;
    for (int k = 0; k < 6; ++k) {
      const glm::vec3 direction = glm::normalize(glm::vec3(rng.NextNormal(), rng.NextNormal(), rng.NextNormal()));
      w.emplace_back(direction * (2.0f * kPi / (3.0f + 2.0f * float(k % 3))), 6.0f * float(rng.NextNormal()));
    }
    return w;
  }();
  float sum = 0.0f;
  for (const glm::vec4& w : waves) sum += std::sin(glm::dot(glm::vec3(w), p) + w.w);
  return std::clamp(sum / 2.5f, -1.0f, 1.0f);
}

float DistanceToSegments(glm::vec3 p, const std::vector<glm::vec3>& points) {
  float best = 1e9f;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const glm::vec3 d = points[k + 1] - points[k];
    const float t = std::clamp(glm::dot(p - points[k], d) / glm::dot(d, d), 0.0f, 1.0f);
    best = std::min(best, glm::length(p - points[k] - t * d));
  }
  return best;
}

// The skin's colour at triangle centre `p` of a blotchy face: darker brows and lips.
glm::vec3 BlotchySkin(glm::vec3 skin, glm::vec3 p, const FaceTemplateInfo& info,
                      const std::vector<glm::vec3>& positions) {
  const auto chain = [&](int first, int last, bool closed) {
    std::vector<glm::vec3> points;
    for (int k = first; k <= last; ++k) points.push_back(positions[info.landmark_vertices[std::size_t(k)]]);
    if (closed) points.push_back(points.front());
    return points;
  };
  glm::vec3 colour = skin * (1.0f + 0.1f * Blotches(p));
  if (std::min(DistanceToSegments(p, chain(17, 21, false)), DistanceToSegments(p, chain(22, 26, false))) < 0.5f) {
    colour *= glm::vec3(0.55f, 0.5f, 0.5f);
  }
  if (DistanceToSegments(p, chain(48, 59, true)) < 0.35f) colour *= glm::vec3(0.85f, 0.65f, 0.65f);
  return colour;
}

}  // namespace

LandmarkDetector& Detector() {
  static LandmarkDetector detector;
  return detector;
}

const IctPhotoSetup& Setup() {
  static const IctPhotoSetup setup = [] {
    IctPhotoSetup s;
    s.info = test::LoadIctTemplateInfo(test::IctRig());
    s.model = BuildPhotoFaceModel(test::IctRig(), s.info, test::IctFaces().identities, {},
                                           &Detector());
    return s;
  }();
  return setup;
}

std::vector<glm::vec3> FaceWithWeights(const PhotoFaceModel& model, const std::vector<double>& weights) {
  std::vector<glm::vec3> face = model.neutral;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += static_cast<float>(weights[i]) * model.identity_modes[i][v];
  }
  return face;
}

RasterView PhotoView(glm::vec3 nose, float yaw_degrees, int size, float distance_cm) {
  RasterView view = RasterView::Orbit(nose, kHalfFrame, size, size, yaw_degrees * kPi / 180.0f);
  if (distance_cm > 0.0f) {
    view.vertical_fov = 2.0f * std::atan(kHalfFrame / distance_cm);
    view.distance = distance_cm;
  }
  return view;
}

RenderStyle SideLight() {
  const float off = 40.0f * kPi / 180.0f;
  // dlib's points follow the hard shadows: the landmark fit's yaw is off by up to 5 degrees.
  return {glm::vec3(-std::sin(off) * 0.7071f, std::sin(off) * 0.7071f, std::cos(off)), 0.1f, false, 6.0f};
}

RenderStyle Blotchy() { return {.blotchy = true}; }

RenderStyle Hard() {
  RenderStyle style = SideLight();
  style.blotchy = true;
  style.noise = 0.02f;
  return style;
}

RgbImage RenderFace(const FaceTemplateInfo& info, const std::vector<glm::vec3>& positions, float yaw_degrees,
                    int size, const RenderStyle& style) {
  Mesh mesh{.positions = positions};
  std::vector<glm::vec3> albedo;
  for (const Triangle& t : test::IctRig().triangles()) {
    const TemplatePart* part = nullptr;
    for (const TemplatePart& p : info.parts) {
      if (t[0] >= p.vertices.first && t[0] <= p.vertices.last) part = &p;
    }
    if (part == nullptr || part->name.starts_with("lacrimal") || part->name.starts_with("eye_blend") ||
        part->name.starts_with("eye_occlusion")) {
      continue;
    }
    mesh.triangles.push_back(t);
    albedo.push_back(PartColour(part->name));
    if (style.blotchy && part->name.starts_with("skin")) {
      albedo.back() = BlotchySkin(albedo.back(), (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0f, info,
                                  positions);
    }
  }
  std::vector<glm::vec3> normals(positions.size());
  ComputeVertexNormals(positions, mesh.triangles, normals);
  for (const Triangle& t : mesh.triangles) {
    for (const std::uint32_t v : t) mesh.corner_normals.push_back(normals[v]);
  }
  const RasterView view = PhotoView(positions[info.landmark_vertices[30]], yaw_degrees, size, style.distance_cm);
  ShadeParams shade;
  shade.light = style.light;
  shade.ambient = style.ambient;
  RgbImage image = Shade(Rasterize(mesh, view), mesh, albedo, view, shade);
  if (style.noise > 0.0f) AddNoise(image, style.noise);
  return image;
}

std::vector<glm::vec2> ExactLandmarks(const FaceTemplateInfo& info, const std::vector<glm::vec3>& rendered,
                                      float yaw_degrees, int size, float distance_cm) {
  const RasterView view = PhotoView(rendered[info.landmark_vertices[30]], yaw_degrees, size, distance_cm);
  std::vector<glm::vec2> pixels;
  for (const std::uint32_t v : info.landmark_vertices) pixels.emplace_back(ProjectToImage(view, rendered[v]));
  return pixels;
}
}  // namespace facerig::test
