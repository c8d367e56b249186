#include "facerig/runtime/blend_plan.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "blend_kernels.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

using Bits = std::vector<std::uint64_t>;

std::size_t WordsFor(std::size_t bits) { return (bits + 63) / 64; }
void SetBit(Bits& bits, std::size_t index) { bits[index / 64] |= std::uint64_t{1} << (index % 64); }

template <typename F>
void ForEachBit(const Bits& bits, F&& f) {
  for (std::size_t w = 0; w < bits.size(); ++w) {
    for (std::uint64_t word = bits[w]; word != 0; word &= word - 1) {
      f(w * 64 + static_cast<std::size_t>(std::countr_zero(word)));
    }
  }
}

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

// Runs of consecutive vertices in a strictly increasing index list; deltas
// numbered from `first_delta` in list order.
void AppendRuns(std::span<const std::uint32_t> vertices, std::uint32_t first_delta, std::vector<DeltaRun>& runs) {
  for (std::size_t i = 0; i < vertices.size();) {
    std::size_t end = i + 1;
    while (end < vertices.size() && vertices[end] == vertices[end - 1] + 1) ++end;
    runs.push_back({vertices[i], static_cast<std::uint32_t>(end - i), first_delta + static_cast<std::uint32_t>(i)});
    i = end;
  }
}

// The normals of the neutral moved by one shape at weight 1, recomputed at
// the shaded vertices only (summed over their triangles, as
// ComputeVertexNormals does).
class ShapeNormals {
 public:
  explicit ShapeNormals(const Rig& rig)
      : rig_(rig), posed_(rig.positions().begin(), rig.positions().end()), sums_(rig.vertex_count()) {}

  void Compute(const BlendShapeView& shape, const std::vector<std::uint32_t>& shaded, const Bits& triangles) {
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) posed_[shape.vertex_indices[i]] += shape.position_deltas[i];
    for (std::uint32_t v : shaded) sums_[v] = glm::vec3(0.0f);
    ForEachBit(triangles, [&](std::size_t t) {
      const Triangle& triangle = rig_.triangles()[t];
      const glm::vec3 n = blend::TriangleNormal(posed_.data(), triangle);
      for (std::uint32_t corner : triangle) sums_[corner] += n;  // only shaded corners are read
    });
    for (std::uint32_t v : shaded) blend::NormaliseSum(sums_[v]);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      posed_[shape.vertex_indices[i]] = rig_.positions()[shape.vertex_indices[i]];
    }
  }
  const glm::vec3& normal(std::uint32_t v) const { return sums_[v]; }

 private:
  const Rig& rig_;
  std::vector<glm::vec3> posed_, sums_;
};

}  // namespace

BlendPlan BlendPlan::Build(const Rig& rig) {
  BlendPlan plan;
  plan.rig_ = &rig;
  plan.vertex_words_ = WordsFor(rig.vertex_count());
  plan.triangle_words_ = WordsFor(rig.triangle_count());
  plan.recomputed_rest_normals_.resize(rig.vertex_count());
  ComputeVertexNormals(rig.positions(), rig.triangles(), plan.recomputed_rest_normals_);
  const VertexTriangles incident(rig);
  ShapeNormals shape_normals(rig);

  Bits moved(plan.vertex_words_), shaded(plan.vertex_words_), reached(plan.triangle_words_);
  std::vector<std::uint32_t> shaded_list;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    std::fill(moved.begin(), moved.end(), 0);
    std::fill(shaded.begin(), shaded.end(), 0);
    std::fill(reached.begin(), reached.end(), 0);
    const BlendShapeView shape = rig.shape(s);
    for (std::uint32_t v : shape.vertex_indices) SetBit(moved, v);
    // A moved vertex changes the normal of every triangle it is a corner of,
    // so of those triangles' corners; their normals sum all their triangles.
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
    plan.moved_.push_back(AppendSpan(moved, plan.pool_));
    plan.shaded_.push_back(AppendSpan(shaded, plan.pool_));
    plan.triangles_.push_back(AppendSpan(reached, plan.pool_));

    const auto first_run = static_cast<std::uint32_t>(plan.runs_.size());
    AppendRuns(shape.vertex_indices, 0, plan.runs_);
    plan.entry_run_ranges_.push_back({first_run, static_cast<std::uint32_t>(plan.runs_.size()) - first_run});

    shape_normals.Compute(shape, shaded_list, reached);
    const auto first_shaded_run = static_cast<std::uint32_t>(plan.runs_.size());
    AppendRuns(shaded_list, static_cast<std::uint32_t>(plan.recomputed_normal_deltas_.size()), plan.runs_);
    plan.shaded_run_ranges_.push_back(
        {first_shaded_run, static_cast<std::uint32_t>(plan.runs_.size()) - first_shaded_run});
    for (std::uint32_t v : shaded_list) {
      plan.recomputed_normal_deltas_.push_back(shape_normals.normal(v) - plan.recomputed_rest_normals_[v]);
    }
  }

  if (rig.has_normal_deltas()) {
    // As BlendJob's kBlendDeltas renormalises every vertex, rest ones too.
    plan.renormalised_rest_normals_.assign(rig.normals().begin(), rig.normals().end());
    for (glm::vec3& n : plan.renormalised_rest_normals_) blend::RenormaliseBlended(n);
  }
  return plan;
}

std::span<const DeltaRun> BlendPlan::entry_runs(std::size_t shape) const {
  return std::span(runs_).subspan(entry_run_ranges_[shape].first, entry_run_ranges_[shape].count);
}

std::span<const DeltaRun> BlendPlan::shaded_runs(std::size_t shape) const {
  return std::span(runs_).subspan(shaded_run_ranges_[shape].first, shaded_run_ranges_[shape].count);
}

std::span<const glm::vec3> BlendPlan::rest_normals(NormalMode mode) const {
  switch (mode) {
    case NormalMode::kRecompute:
    case NormalMode::kBlendRecomputedDeltas: return recomputed_rest_normals_;
    case NormalMode::kBlendDeltas: return renormalised_rest_normals_;
    case NormalMode::kNone: break;
  }
  return {};
}

BlendState::BlendState(const BlendPlan& plan)
    : plan_(&plan),
      moved_(plan.vertex_words()),
      shaded_(plan.vertex_words()),
      next_moved_(plan.vertex_words()),
      next_shaded_(plan.vertex_words()),
      next_triangles_(plan.triangle_words()) {}

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
  if (normals_ != nullptr) work.shaded_vertices = count(shaded_);
  if (normal_mode_ == NormalMode::kRecompute) work.triangles = count(next_triangles_);
  return work;
}

}  // namespace facerig
