#include "normal_terms.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "blend_kernels.h"

namespace facerig {
namespace {

void SetBit(bits::Words& set, std::size_t index) { set[index / 64] |= std::uint64_t{1} << (index % 64); }
void ClearBit(bits::Words& set, std::size_t index) { set[index / 64] &= ~(std::uint64_t{1} << (index % 64)); }

// A triangle's two edges from its first corner, in a per-vertex field.
struct Edges {
  glm::vec3 e1, e2;
  Edges(const glm::vec3* field, const Triangle& t) : e1(field[t[1]] - field[t[0]]), e2(field[t[2]] - field[t[0]]) {}
};

}  // namespace

NormalTerms::NormalTerms(const Rig& rig, float tolerance)
    : rig_(rig),
      tolerance_(tolerance),
      rest_sums_(rig.vertex_count(), glm::vec3(0.0f)),
      first_incident_(rig.vertex_count() + 1, 0),
      first_(rig.vertex_count(), glm::vec3(0.0f)),
      second_(rig.vertex_count(), glm::vec3(0.0f)),
      first_moved_((rig.vertex_count() + 63) / 64),
      second_moved_(first_moved_.size()),
      triangle_seen_((rig.triangle_count() + 63) / 64),
      sums_(rig.vertex_count(), glm::vec3(0.0f)),
      quadratics_(rig.vertex_count(), glm::vec3(0.0f)),
      vertex_seen_(first_moved_.size()) {
  for (const Triangle& t : rig.triangles()) {
    const glm::vec3 n = blend::TriangleNormal(rig.positions().data(), t);
    for (std::uint32_t corner : t) rest_sums_[corner] += n;
    for (std::uint32_t corner : t) ++first_incident_[corner + 1];
  }
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) first_incident_[v + 1] += first_incident_[v];
  incident_.resize(first_incident_.back());
  std::vector<std::uint32_t> next(first_incident_.begin(), first_incident_.end() - 1);
  for (std::size_t t = 0; t < rig.triangle_count(); ++t) {
    for (std::uint32_t corner : rig.triangles()[t]) incident_[next[corner]++] = static_cast<std::uint32_t>(t);
  }
}

void NormalTerms::Scatter(std::size_t s, std::vector<glm::vec3>& dense, bits::Words& moved) const {
  const BlendShapeView shape = rig_.shape(s);
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    dense[shape.vertex_indices[i]] = shape.position_deltas[i];
    SetBit(moved, shape.vertex_indices[i]);
  }
}

void NormalTerms::Clear(std::size_t s, std::vector<glm::vec3>& dense, bits::Words& moved) const {
  for (std::uint32_t v : rig_.shape(s).vertex_indices) {
    dense[v] = glm::vec3(0.0f);
    ClearBit(moved, v);
  }
}

void NormalTerms::Select(std::size_t s) {
  Clear(selected_, first_, first_moved_);
  selected_ = s;
  Scatter(s, first_, first_moved_);
  touched_triangles_.clear();
  for (std::uint32_t v : rig_.shape(s).vertex_indices) {
    for (std::uint32_t k = first_incident_[v]; k < first_incident_[v + 1]; ++k) {
      const std::uint32_t t = incident_[k];
      if (bits::Test(triangle_seen_, t)) continue;
      SetBit(triangle_seen_, t);
      touched_triangles_.push_back(t);
    }
  }
  for (std::uint32_t t : touched_triangles_) ClearBit(triangle_seen_, t);
  std::sort(touched_triangles_.begin(), touched_triangles_.end());
}

void NormalTerms::Add(const Triangle& t, const glm::vec3& value) {
  for (std::uint32_t corner : t) {
    sums_[corner] += value;
    if (!bits::Test(vertex_seen_, corner)) {
      SetBit(vertex_seen_, corner);
      touched_vertices_.push_back(corner);
    }
  }
}

template <typename Keep>
void NormalTerms::Take(VertexTerms* out, Keep&& keep) {
  out->vertices.clear();
  out->values.clear();
  std::sort(touched_vertices_.begin(), touched_vertices_.end());
  for (std::uint32_t v : touched_vertices_) {
    if (keep(v)) {
      out->vertices.push_back(v);
      out->values.push_back(sums_[v]);
    }
    sums_[v] = glm::vec3(0.0f);
    ClearBit(vertex_seen_, v);
  }
  touched_vertices_.clear();
}

void NormalTerms::Single(VertexTerms* change, VertexTerms* quadratic) {
  for (std::uint32_t index : touched_triangles_) {
    const Triangle& t = rig_.triangles()[index];
    const Edges e(rig_.positions().data(), t), d(first_.data(), t);
    const glm::vec3 q = glm::cross(d.e1, d.e2);
    Add(t, glm::cross(e.e1, d.e2) + glm::cross(d.e1, e.e2) + q);
    for (std::uint32_t corner : t) quadratics_[corner] += q;
  }
  const auto turns = [&](const glm::vec3& term, std::uint32_t v) {
    return glm::length(term) > tolerance_ * glm::length(rest_sums_[v]);
  };
  // Q matters most at w = 1/2, where w^2 - w = -1/4.
  Take(change, [&](std::uint32_t v) { return turns(sums_[v], v) || turns(0.25f * quadratics_[v], v); });
  quadratic->vertices.clear();
  quadratic->values.clear();
  for (std::uint32_t v : change->vertices) {
    if (turns(0.25f * quadratics_[v], v)) {
      quadratic->vertices.push_back(v);
      quadratic->values.push_back(quadratics_[v]);
    }
  }
  for (std::uint32_t index : touched_triangles_) {
    for (std::uint32_t corner : rig_.triangles()[index]) quadratics_[corner] = glm::vec3(0.0f);
  }
}

void NormalTerms::Pair(std::size_t t, VertexTerms* cross) {
  Scatter(t, second_, second_moved_);
  for (std::uint32_t index : touched_triangles_) {
    const Triangle& tri = rig_.triangles()[index];
    if (!bits::Test(second_moved_, tri[0]) && !bits::Test(second_moved_, tri[1]) && !bits::Test(second_moved_, tri[2])) {
      continue;
    }
    const Edges s(first_.data(), tri), u(second_.data(), tri);
    Add(tri, glm::cross(s.e1, u.e2) + glm::cross(u.e1, s.e2));
  }
  Clear(t, second_, second_moved_);
  Take(cross, [&](std::uint32_t v) { return 0.25f * glm::length(sums_[v]) > tolerance_ * glm::length(rest_sums_[v]); });
}

}  // namespace facerig
