#include "facerig/runtime/rig_builder.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include <glm/geometric.hpp>

#include "blend_kernels.h"

namespace facerig {
namespace {

bool IsFinite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool IsFinite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

bool Fail(std::string* problem, std::string text) {
  if (problem) *problem = std::move(text);
  return false;
}

template <typename Vec>
bool AllFinite(const std::vector<Vec>& values, const char* what, std::string* problem) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!IsFinite(values[i])) {
      return Fail(problem, std::string(what) + " " + std::to_string(i) + " is not finite");
    }
  }
  return true;
}

// True when any shape carries normal deltas (then every non-empty one must).
bool HasNormalDeltas(const std::vector<RawBlendShape>& shapes) {
  for (const RawBlendShape& shape : shapes) {
    if (!shape.normal_deltas.empty()) return true;
  }
  return false;
}

bool ValidateShape(const RawBlendShape& shape, std::size_t vertex_count, bool expect_normals,
                   std::string* problem) {
  const std::string where = "shape '" + shape.name + "': ";
  if (shape.name.empty()) return Fail(problem, "a shape has an empty name");
  if (shape.position_deltas.size() != shape.vertex_indices.size()) {
    return Fail(problem, where + std::to_string(shape.vertex_indices.size()) + " indices but " +
                             std::to_string(shape.position_deltas.size()) + " position deltas");
  }
  // An empty shape is valid in any rig; otherwise all shapes have normal deltas or none.
  const bool has_normals = !shape.normal_deltas.empty();
  if ((expect_normals && shape.normal_deltas.size() != shape.vertex_indices.size()) ||
      (!expect_normals && has_normals)) {
    return Fail(problem, where + "normal deltas must be given for every entry of every shape, or none");
  }
  std::vector<std::uint32_t> sorted = shape.vertex_indices;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (sorted[i] >= vertex_count) {
      return Fail(problem, where + "vertex index " + std::to_string(sorted[i]) +
                               " >= vertex count " + std::to_string(vertex_count));
    }
    if (i > 0 && sorted[i] == sorted[i - 1]) {
      return Fail(problem, where + "vertex index " + std::to_string(sorted[i]) + " appears twice");
    }
  }
  for (std::size_t i = 0; i < shape.position_deltas.size(); ++i) {
    if (!IsFinite(shape.position_deltas[i]) ||
        (expect_normals && !IsFinite(shape.normal_deltas[i]))) {
      return Fail(problem, where + "delta of vertex " + std::to_string(shape.vertex_indices[i]) +
                               " is not finite");
    }
  }
  return true;
}

}  // namespace

bool RawRig::Validate(std::string* problem) const {
  const std::size_t n = positions.size();
  if (n == 0) return Fail(problem, "the rig has no vertices");
  if (n > std::size_t{0xFFFFFFF0u}) return Fail(problem, "too many vertices");
  if (triangles.empty()) return Fail(problem, "the rig has no triangles");
  if (!normals.empty() && normals.size() != n) {
    return Fail(problem, std::to_string(normals.size()) + " normals for " + std::to_string(n) +
                             " vertices");
  }
  if (!uvs.empty() && uvs.size() != n) {
    return Fail(problem, std::to_string(uvs.size()) + " UVs for " + std::to_string(n) + " vertices");
  }
  if (!AllFinite(positions, "position", problem) || !AllFinite(normals, "normal", problem) ||
      !AllFinite(uvs, "UV", problem)) {
    return false;
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= n) {
        return Fail(problem, "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                 " >= vertex count " + std::to_string(n));
      }
    }
  }
  std::size_t next_triangle = 0;
  for (const RawPart& part : parts) {
    if (part.name.empty()) return Fail(problem, "a part has an empty name");
    if (part.material < -1 || part.material >= static_cast<std::int64_t>(materials.size())) {
      return Fail(problem, "part '" + part.name + "' names material " + std::to_string(part.material) +
                               " of " + std::to_string(materials.size()));
    }
    if (part.first_triangle != next_triangle || part.triangle_count == 0) {
      return Fail(problem, "part '" + part.name + "' does not continue at triangle " +
                               std::to_string(next_triangle) + " (parts must tile the triangles)");
    }
    next_triangle += part.triangle_count;
  }
  if (!parts.empty() && next_triangle != triangles.size()) {
    return Fail(problem, "parts cover " + std::to_string(next_triangle) + " of " +
                             std::to_string(triangles.size()) + " triangles");
  }
  if (!ValidateMaterials(materials, images, problem)) return false;
  const bool expect_normals = HasNormalDeltas(shapes);
  std::unordered_set<std::string> names;
  for (const RawBlendShape& shape : shapes) {
    if (!ValidateShape(shape, n, expect_normals, problem)) return false;
    if (!names.insert(shape.name).second) {
      return Fail(problem, "shape name '" + shape.name + "' appears twice");
    }
  }
  return true;
}

RawBlendShape MakeSparseShape(std::string name, std::span<const glm::vec3> dense_position_deltas,
                              std::span<const glm::vec3> dense_normal_deltas,
                              float drop_threshold, float normal_drop_threshold) {
  RawBlendShape shape;
  shape.name = std::move(name);
  const bool with_normals = !dense_normal_deltas.empty();
  const float threshold_sq = drop_threshold * drop_threshold;
  const float normal_threshold_sq = normal_drop_threshold * normal_drop_threshold;
  for (std::size_t i = 0; i < dense_position_deltas.size(); ++i) {
    const glm::vec3 d = dense_position_deltas[i];
    bool keep = glm::dot(d, d) > threshold_sq;
    if (with_normals) {
      const glm::vec3 dn = dense_normal_deltas[i];
      keep = keep || glm::dot(dn, dn) > normal_threshold_sq;
    }
    if (!keep) continue;
    shape.vertex_indices.push_back(static_cast<std::uint32_t>(i));
    shape.position_deltas.push_back(d);
    if (with_normals) shape.normal_deltas.push_back(dense_normal_deltas[i]);
  }
  return shape;
}

void ComputeVertexNormals(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                          std::span<glm::vec3> normals) {
  std::fill(normals.begin(), normals.end(), glm::vec3(0.0f));
  for (const Triangle& t : triangles) {
    const glm::vec3 n = blend::TriangleNormal(positions.data(), t);
    normals[t[0]] += n;
    normals[t[1]] += n;
    normals[t[2]] += n;
  }
  blend::NormaliseSums(normals.data(), normals.size());
}

std::optional<Rig> RigBuilder::Build(RawRig raw, std::string* problem) {
  if (!raw.Validate(problem)) return std::nullopt;
  Rig rig;
  const std::size_t n = raw.positions.size();
  rig.positions_ = std::move(raw.positions);
  rig.triangles_ = std::move(raw.triangles);
  rig.uvs_ = std::move(raw.uvs);
  rig.units_ = raw.units;
  rig.up_axis_ = raw.up_axis;

  rig.normals_.resize(n);
  if (raw.normals.empty()) {
    ComputeVertexNormals(rig.positions_, rig.triangles_, rig.normals_);
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      // Unit normals are kept bit for bit (renormalising is not idempotent in
      // float), so a rig survives any number of save/load round trips exactly.
      const float length = glm::length(raw.normals[i]);
      if (std::abs(length - 1.0f) <= 1e-6f) {
        rig.normals_[i] = raw.normals[i];
      } else {
        rig.normals_[i] = length > 0.0f ? raw.normals[i] / length : glm::vec3(0.0f, 0.0f, 1.0f);
      }
    }
  }

  glm::vec3 lo = rig.positions_.front(), hi = lo;
  for (const glm::vec3& p : rig.positions_) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  rig.bounding_diagonal_ = glm::length(hi - lo);

  if (raw.parts.empty()) {
    raw.parts.push_back({"mesh", 0, static_cast<std::uint32_t>(rig.triangles_.size())});
  }
  for (const RawPart& raw_part : raw.parts) {
    Part part{raw_part.name, raw_part.first_triangle, raw_part.triangle_count, 0, 0, raw_part.material};
    std::uint32_t lo_v = UINT32_MAX, hi_v = 0;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (std::uint32_t v : rig.triangles_[t]) {
        lo_v = std::min(lo_v, v);
        hi_v = std::max(hi_v, v);
      }
    }
    part.first_vertex = lo_v;
    part.vertex_count = hi_v - lo_v + 1;
    rig.parts_.push_back(std::move(part));
  }

  rig.materials_ = std::move(raw.materials);
  rig.images_ = std::move(raw.images);
  rig.has_normal_deltas_ = HasNormalDeltas(raw.shapes);
  std::size_t total = 0;
  for (const RawBlendShape& shape : raw.shapes) total += shape.vertex_indices.size();
  rig.shape_vertex_indices_.reserve(total);
  rig.shape_position_deltas_.reserve(total);
  if (rig.has_normal_deltas_) rig.shape_normal_deltas_.reserve(total);
  std::vector<std::uint32_t> order;
  for (RawBlendShape& shape : raw.shapes) {
    order.resize(shape.vertex_indices.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return shape.vertex_indices[a] < shape.vertex_indices[b];
    });
    rig.shape_ranges_.push_back({static_cast<std::uint32_t>(rig.shape_vertex_indices_.size()),
                                 static_cast<std::uint32_t>(order.size())});
    for (std::uint32_t i : order) {
      rig.shape_vertex_indices_.push_back(shape.vertex_indices[i]);
      rig.shape_position_deltas_.push_back(shape.position_deltas[i]);
      if (rig.has_normal_deltas_) rig.shape_normal_deltas_.push_back(shape.normal_deltas[i]);
    }
    rig.shape_names_.push_back(std::move(shape.name));
  }
  return rig;
}

RawRig RigBuilder::ToRaw(const Rig& rig) {
  RawRig raw;
  raw.positions.assign(rig.positions().begin(), rig.positions().end());
  raw.normals.assign(rig.normals().begin(), rig.normals().end());
  raw.triangles.assign(rig.triangles().begin(), rig.triangles().end());
  raw.uvs.assign(rig.uvs().begin(), rig.uvs().end());
  for (const Part& part : rig.parts()) {
    raw.parts.push_back({part.name, part.first_triangle, part.triangle_count, part.material});
  }
  raw.materials.assign(rig.materials().begin(), rig.materials().end());
  raw.images.assign(rig.images().begin(), rig.images().end());
  raw.units = rig.units();
  raw.up_axis = rig.up_axis();
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView view = rig.shape(s);
    RawBlendShape shape;
    shape.name = std::string(view.name);
    shape.vertex_indices.assign(view.vertex_indices.begin(), view.vertex_indices.end());
    shape.position_deltas.assign(view.position_deltas.begin(), view.position_deltas.end());
    shape.normal_deltas.assign(view.normal_deltas.begin(), view.normal_deltas.end());
    raw.shapes.push_back(std::move(shape));
  }
  return raw;
}

}  // namespace facerig
