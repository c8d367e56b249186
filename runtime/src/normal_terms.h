// The recomputed normals' sums as polynomials in the shape weights, for
// BlendPlan (kBlendRecomputedDeltas). A vertex's normal is its normalised sum
// of triangle normals cross(e1, e2), and a triangle's edges are linear in the
// weights, so the sum is exactly
//   S = S0 + sum_s w_s L_s + sum_s w_s^2 Q_s + sum_{s<t} w_s w_t Q_st
// with L_s = sum cross(e1, d2_s) + cross(d1_s, e2), Q_s = sum cross(d1_s, d2_s)
// and Q_st = sum cross(d1_s, d2_t) + cross(d1_t, d2_s) over the vertex's
// triangles (e: the neutral's edges, d_s: shape s's edge deltas).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "bit_runs.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// Values at increasing vertices.
struct VertexTerms {
  std::vector<std::uint32_t> vertices;
  std::vector<glm::vec3> values;
};

class NormalTerms {
 public:
  // Terms are kept where they turn a vertex's normal by more than
  // `tolerance` radians (|term| > tolerance * |S0|), Q at w = 1/2 and Q_st at
  // w_s = w_t = 1/2.
  NormalTerms(const Rig& rig, float tolerance);

  const std::vector<glm::vec3>& rest_sums() const { return rest_sums_; }

  // Makes shape s the first of the terms below.
  void Select(std::size_t s);
  // dS = L_s + Q_s (the change at weight 1, kept also where Q_s is) and Q_s.
  void Single(VertexTerms* change, VertexTerms* quadratic);
  // Q_st for the selected shape s and a later shape t; empty when they
  // share no triangle.
  void Pair(std::size_t t, VertexTerms* cross);

 private:
  // Shape `s`'s deltas at every vertex (zero where it has none) and the set it moves.
  void Scatter(std::size_t s, std::vector<glm::vec3>& dense, bits::Words& moved) const;
  void Clear(std::size_t s, std::vector<glm::vec3>& dense, bits::Words& moved) const;
  void Add(const Triangle& t, const glm::vec3& value);
  // The accumulated sums where `keep` says, then cleared.
  template <typename Keep>
  void Take(VertexTerms* out, Keep&& keep);

  const Rig& rig_;
  float tolerance_;
  std::vector<glm::vec3> rest_sums_;
  std::vector<std::uint32_t> first_incident_, incident_;  // vertex -> triangles (CSR)
  std::size_t selected_ = 0;
  std::vector<std::uint32_t> touched_triangles_;  // with a corner the selected shape moves
  std::vector<glm::vec3> first_, second_;         // dense deltas of the selected shape and of t
  bits::Words first_moved_, second_moved_, triangle_seen_;
  std::vector<glm::vec3> sums_, quadratics_;  // accumulators
  std::vector<std::uint32_t> touched_vertices_;
  bits::Words vertex_seen_;
};

}  // namespace facerig
