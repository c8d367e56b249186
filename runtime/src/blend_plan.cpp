#include "facerig/runtime/blend_plan.h"

#include <algorithm>
#include <cmath>

#include "bit_runs.h"
#include "blend_kernels.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

using Bits = bits::Words;

std::size_t WordsFor(std::size_t bits) { return (bits + 63) / 64; }
void SetBit(Bits& bits, std::size_t index) { bits[index / 64] |= std::uint64_t{1} << (index % 64); }

using bits::ForEachBit;

// For each vertex, the triangles that use it (CSR: begin[v]..begin[v + 1]).
struct VertexTriangles {
  std::vector<std::uint32_t> begin, triangles;

  explicit VertexTriangles(const Rig& rig) : begin(rig.vertex_count() + 1, 0) {
    for (const Triangle& t : rig.triangles()) {
      for (std::uint32_t v : t) ++begin[v + 1];
    }
    for (std::size_t v = 0; v < rig.vertex_count(); ++v) begin[v + 1] += begin[v];
    triangles.resize(begin.back());
    std::vector<std::uint32_t> next(begin.begin(), begin.end() - 1);
    for (std::size_t t = 0; t < rig.triangle_count(); ++t) {
      for (std::uint32_t v : rig.triangles()[t]) triangles[next[v]++] = static_cast<std::uint32_t>(t);
    }
  }
};

// Appends the non-zero word range of `bits` to the pool.
BitSpan AppendSpan(const Bits& bits, Bits& pool) {
  const auto nonzero = [](std::uint64_t word) { return word != 0; };
  const auto first = std::find_if(bits.begin(), bits.end(), nonzero);
  if (first == bits.end()) return {};
  const auto last = std::find_if(bits.rbegin(), bits.rend(), nonzero).base();
  BitSpan span;
  span.first_word = static_cast<std::uint32_t>(first - bits.begin());
  span.word_count = static_cast<std::uint32_t>(last - first);
  span.offset = static_cast<std::uint32_t>(pool.size());
  pool.insert(pool.end(), first, last);
  return span;
}

// The triangle normal sums of the neutral moved by one shape at `weight`,
// at the shaded vertices only (the sums of the other vertices are stale).
class ShapeSums {
 public:
  explicit ShapeSums(const Rig& rig)
      : rig_(rig), posed_(rig.positions().begin(), rig.positions().end()), sums_(rig.vertex_count()) {}

  void Compute(const BlendShapeView& shape, float weight, const std::vector<std::uint32_t>& shaded,
               const Bits& triangles) {
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      posed_[shape.vertex_indices[i]] += weight * shape.position_deltas[i];
    }
    for (std::uint32_t v : shaded) sums_[v] = glm::vec3(0.0f);
    ForEachBit(triangles, [&](std::size_t t) {
      const Triangle& triangle = rig_.triangles()[t];
      const glm::vec3 n = blend::TriangleNormal(posed_.data(), triangle);
      for (std::uint32_t corner : triangle) sums_[corner] += n;
    });
    for (std::uint32_t v : shape.vertex_indices) posed_[v] = rig_.positions()[v];
  }
  const glm::vec3& sum(std::uint32_t v) const { return sums_[v]; }

 private:
  const Rig& rig_;
  std::vector<glm::vec3> posed_, sums_;
};

// One shape's dS and Q over its shaded vertices, kept where they turn the
// normal by more than the tolerance (Q at its largest, w = 1/2).
struct SumDeltas {
  std::vector<std::uint32_t> sum_vertices, quadratic_vertices;
  std::vector<glm::vec3> sums, quadratics;

  void Keep(std::span<const glm::vec3> rest_sums, const std::vector<std::uint32_t>& shaded, const ShapeSums& full,
            const ShapeSums& half) {
    *this = {};
    for (std::uint32_t v : shaded) {
      const glm::vec3 change = full.sum(v) - rest_sums[v];
      const glm::vec3 linear = 4.0f * (half.sum(v) - rest_sums[v]) - change;  // S(1/2) = S0 + L/2 + Q/4
      const glm::vec3 quadratic = change - linear;
      const float limit = BlendPlan::kNormalTolerance * glm::length(rest_sums[v]);
      const bool keep_quadratic = 0.25f * glm::length(quadratic) > limit;
      if (glm::length(change) > limit || keep_quadratic) {
        sum_vertices.push_back(v);
        sums.push_back(change);
      }
      if (keep_quadratic) {
        quadratic_vertices.push_back(v);
        quadratics.push_back(quadratic);
      }
    }
  }
};

}  // namespace

BlendPlan BlendPlan::Build(const Rig& rig) {
  BlendPlan plan;
  plan.rig_ = &rig;
  plan.vertex_words_ = WordsFor(rig.vertex_count());
  plan.recomputed_rest_normals_.resize(rig.vertex_count());
  ComputeVertexNormals(rig.positions(), rig.triangles(), plan.recomputed_rest_normals_);
  plan.rest_sums_.assign(rig.vertex_count(), glm::vec3(0.0f));
  for (const Triangle& t : rig.triangles()) {
    const glm::vec3 n = blend::TriangleNormal(rig.positions().data(), t);
    for (std::uint32_t corner : t) plan.rest_sums_[corner] += n;
  }
  const VertexTriangles incident(rig);
  ShapeSums full(rig), half(rig);
  SumDeltas kept;
  Bits blended(plan.vertex_words_);

  Bits moved(plan.vertex_words_), shaded(plan.vertex_words_), reached(WordsFor(rig.triangle_count()));
  std::vector<std::uint32_t> shaded_list;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    std::fill(moved.begin(), moved.end(), 0);
    std::fill(shaded.begin(), shaded.end(), 0);
    std::fill(reached.begin(), reached.end(), 0);
    const BlendShapeView shape = rig.shape(s);
    for (std::uint32_t v : shape.vertex_indices) SetBit(moved, v);
    plan.moved_.push_back(AppendSpan(moved, plan.pool_));
    plan.entry_runs_.push_back(plan.AppendRuns(shape.vertex_indices, 0));

    // A moved vertex turns every triangle it is a corner of, so the normals
    // of those triangles' corners (shaded); each sums all its triangles (reached).
    for (std::uint32_t v : shape.vertex_indices) {
      for (std::uint32_t k = incident.begin[v]; k < incident.begin[v + 1]; ++k) {
        for (std::uint32_t corner : rig.triangles()[incident.triangles[k]]) SetBit(shaded, corner);
      }
    }
    shaded_list.clear();
    ForEachBit(shaded, [&](std::size_t v) { shaded_list.push_back(static_cast<std::uint32_t>(v)); });
    for (std::uint32_t v : shaded_list) {
      for (std::uint32_t k = incident.begin[v]; k < incident.begin[v + 1]; ++k) SetBit(reached, incident.triangles[k]);
    }
    full.Compute(shape, 1.0f, shaded_list, reached);
    half.Compute(shape, 0.5f, shaded_list, reached);
    kept.Keep(plan.rest_sums_, shaded_list, full, half);
    plan.sum_runs_.push_back(plan.AppendRuns(kept.sum_vertices, static_cast<std::uint32_t>(plan.sum_deltas_.size())));
    plan.sum_deltas_.insert(plan.sum_deltas_.end(), kept.sums.begin(), kept.sums.end());
    plan.quadratic_runs_.push_back(
        plan.AppendRuns(kept.quadratic_vertices, static_cast<std::uint32_t>(plan.quadratic_deltas_.size())));
    plan.quadratic_deltas_.insert(plan.quadratic_deltas_.end(), kept.quadratics.begin(), kept.quadratics.end());
    std::fill(blended.begin(), blended.end(), 0);
    for (std::uint32_t v : kept.sum_vertices) SetBit(blended, v);
    plan.blended_.push_back(AppendSpan(blended, plan.pool_));
  }

  if (rig.has_normal_deltas()) {
    // As BlendJob's kBlendDeltas renormalises every vertex, rest ones too.
    plan.renormalised_rest_normals_.assign(rig.normals().begin(), rig.normals().end());
    for (glm::vec3& n : plan.renormalised_rest_normals_) blend::RenormaliseBlended(n);
  }
  return plan;
}

BlendPlan::RunList BlendPlan::AppendRuns(std::span<const std::uint32_t> vertices, std::uint32_t first_delta) {
  RunList list;
  list.first = static_cast<std::uint32_t>(runs_.size());
  for (std::size_t i = 0; i < vertices.size();) {
    std::size_t end = i + 1;
    while (end < vertices.size() && vertices[end] == vertices[end - 1] + 1) ++end;
    runs_.push_back({vertices[i], static_cast<std::uint32_t>(end - i), first_delta + static_cast<std::uint32_t>(i)});
    i = end;
  }
  list.count = static_cast<std::uint32_t>(runs_.size()) - list.first;
  return list;
}

std::span<const glm::vec3> BlendPlan::rest_normals(NormalMode mode) const {
  switch (mode) {
    case NormalMode::kBlendRecomputedDeltas: return recomputed_rest_normals_;
    case NormalMode::kBlendDeltas: return renormalised_rest_normals_;
    case NormalMode::kNone:
    case NormalMode::kRecompute: break;
  }
  return {};
}

BlendState::BlendState(const BlendPlan& plan)
    : plan_(&plan),
      moved_(plan.vertex_words()),
      shaded_(plan.vertex_words()),
      next_moved_(plan.vertex_words()),
      next_shaded_(plan.vertex_words()),
      active_(plan.rig().shape_count()) {}

void BlendState::Reset() {
  positions_ = nullptr;
  normals_ = nullptr;
  normal_mode_ = NormalMode::kNone;
}

BlendWork BlendState::LastWork() const {
  const auto count = [](const std::vector<std::uint64_t>& bits) {
    std::size_t n = 0;
    for (std::uint64_t word : bits) n += static_cast<std::size_t>(std::popcount(word));
    return n;
  };
  BlendWork work;
  if (positions_ == nullptr) return work;
  work.moved_vertices = count(moved_);
  if (normal_mode_ == NormalMode::kBlendDeltas || normal_mode_ == NormalMode::kBlendRecomputedDeltas) {
    work.shaded_vertices = count(shaded_);
  }
  return work;
}

}  // namespace facerig
