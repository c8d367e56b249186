#include "facerig/runtime/rig_surface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

// Whether `surface` lies on the rig: its vertices, and its triangles in the rig's order.
std::optional<std::string> SurfaceMismatch(const Rig& rig, const Mesh& surface) {
  std::string problem;
  if (!surface.Validate(&problem)) return "the surface mesh is invalid: " + problem;
  const auto finite = [](const glm::vec2& uv) { return std::isfinite(uv.x) && std::isfinite(uv.y); };
  if (!std::all_of(surface.corner_uvs.begin(), surface.corner_uvs.end(), finite)) {
    return std::string("the surface mesh has a UV that is not finite");
  }
  if (surface.vertex_count() != rig.vertex_count() ||
      !std::equal(surface.triangles.begin(), surface.triangles.end(), rig.triangles().begin(),
                  rig.triangles().end())) {
    return std::string("the surface mesh's vertices or triangles are not the rig's");
  }
  return std::nullopt;
}

// A rig with one vertex per distinct (vertex, corner UV) of `surface`: the
// rig's vertices first, then copies at UV seams with the vertex's normal and
// shape deltas; the parts split into runs of one material, which they name.
class SeamSplitter {
 public:
  SeamSplitter(const Rig& rig, const Mesh& surface) : rig_(rig), surface_(surface) {}

  RawRig Split() {
    RawRig raw = RigBuilder::ToRaw(rig_);
    raw.normals.assign(rig_.normals().begin(), rig_.normals().end());  // as they are, not recomputed
    if (!surface_.corner_uvs.empty()) SplitSeams(&raw);
    if (!surface_.triangle_materials.empty()) SplitPartsByMaterial(&raw);
    return raw;
  }

 private:
  void SplitSeams(RawRig* raw) {
    raw->uvs = PerVertexAttributes(surface_).uvs;
    std::map<std::tuple<std::uint32_t, float, float>, std::uint32_t> copy_of;  // (vertex, u, v) -> copy
    for (std::size_t t = 0; t < raw->triangles.size(); ++t) {
      for (std::size_t c = 0; c < 3; ++c) {
        const std::uint32_t v = raw->triangles[t][c];
        const glm::vec2 uv = surface_.corner_uvs[t * 3 + c];
        if (uv == raw->uvs[v]) continue;
        const auto [it, added] =
            copy_of.emplace(std::make_tuple(v, uv.x, uv.y), static_cast<std::uint32_t>(raw->positions.size()));
        if (added) {
          copies_.push_back(v);
          raw->positions.push_back(raw->positions[v]);
          raw->normals.push_back(raw->normals[v]);
          raw->uvs.push_back(uv);
        }
        raw->triangles[t][c] = it->second;
      }
    }
    for (RawBlendShape& shape : raw->shapes) AddCopies(&shape);
  }

  // Copies are appended in order after every rig vertex, so the shape's
  // indices stay strictly increasing.
  void AddCopies(RawBlendShape* shape) const {
    const std::vector<std::uint32_t> originals = shape->vertex_indices;  // appending invalidates iterators
    for (std::size_t k = 0; k < copies_.size(); ++k) {
      const auto it = std::lower_bound(originals.begin(), originals.end(), copies_[k]);
      if (it == originals.end() || *it != copies_[k]) continue;
      const auto entry = static_cast<std::size_t>(it - originals.begin());
      shape->vertex_indices.push_back(static_cast<std::uint32_t>(rig_.vertex_count() + k));
      const glm::vec3 position_delta = shape->position_deltas[entry];  // a copy: push_back may reallocate
      shape->position_deltas.push_back(position_delta);
      if (!shape->normal_deltas.empty()) {
        const glm::vec3 normal_delta = shape->normal_deltas[entry];
        shape->normal_deltas.push_back(normal_delta);
      }
    }
  }

  void SplitPartsByMaterial(RawRig* raw) const {
    std::vector<RawPart> runs;
    for (const RawPart& part : raw->parts) {
      for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
        const auto material = static_cast<std::int32_t>(surface_.triangle_materials[t]);
        if (t == part.first_triangle || material != runs.back().material) runs.push_back({part.name, t, 0, material});
        ++runs.back().triangle_count;
      }
    }
    raw->parts = std::move(runs);
    raw->materials = surface_.materials;
    raw->images = surface_.images;
  }

  const Rig& rig_;
  const Mesh& surface_;
  std::vector<std::uint32_t> copies_;  // the rig vertex each copy repeats
};

}  // namespace

std::optional<Rig> RigWithSurface(const Rig& rig, const Mesh& surface, std::string* problem) {
  if (const std::optional<std::string> mismatch = SurfaceMismatch(rig, surface)) {
    if (problem) *problem = *mismatch;
    return std::nullopt;
  }
  std::string build_problem;
  std::optional<Rig> dressed = RigBuilder::Build(SeamSplitter(rig, surface).Split(), &build_problem);
  if (!dressed && problem) *problem = "the dressed rig is invalid: " + build_problem;
  return dressed;
}

}  // namespace facerig
