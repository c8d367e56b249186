#include "facerig/runtime/blend_plan.h"

#include <algorithm>
#include <cmath>

#include "bit_runs.h"
#include "blend_kernels.h"
#include "facerig/runtime/rig_builder.h"
#include "normal_terms.h"

namespace facerig {
namespace {

using Bits = bits::Words;

std::size_t WordsFor(std::size_t bits) { return (bits + 63) / 64; }
void SetBit(Bits& bits, std::size_t index) { bits[index / 64] |= std::uint64_t{1} << (index % 64); }


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

}  // namespace

BlendPlan BlendPlan::Build(const Rig& rig) {
  BlendPlan plan;
  plan.rig_ = &rig;
  plan.vertex_words_ = WordsFor(rig.vertex_count());
  Bits moved(plan.vertex_words_);
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    std::fill(moved.begin(), moved.end(), 0);
    for (std::uint32_t v : shape.vertex_indices) SetBit(moved, v);
    plan.moved_.push_back(AppendSpan(moved, plan.pool_));
    plan.entry_runs_.push_back(plan.AppendRuns(shape.vertex_indices, 0));
  }
  plan.BuildNormalTerms();
  if (rig.has_normal_deltas()) {
    // As BlendJob's kBlendDeltas renormalises every vertex, rest ones too.
    plan.renormalised_rest_normals_.assign(rig.normals().begin(), rig.normals().end());
    for (glm::vec3& n : plan.renormalised_rest_normals_) blend::RenormaliseBlended(n);
  }
  return plan;
}

void BlendPlan::BuildNormalTerms() {
  const std::size_t shapes = rig_->shape_count();
  NormalTerms terms(*rig_, kNormalTolerance);
  rest_sums_ = terms.rest_sums();
  recomputed_rest_normals_ = rest_sums_;
  blend::NormaliseSums(recomputed_rest_normals_.data(), recomputed_rest_normals_.size());  // ComputeVertexNormals'
  std::vector<Bits> blended(shapes, Bits(vertex_words_));
  pair_runs_.assign(shapes * shapes, {});
  VertexTerms change, quadratic, cross;
  for (std::size_t s = 0; s < shapes; ++s) {
    terms.Select(s);
    terms.Single(&change, &quadratic);
    sum_runs_.push_back(AppendTerms(change, sum_deltas_));
    quadratic_runs_.push_back(AppendTerms(quadratic, quadratic_deltas_));
    for (std::uint32_t v : change.vertices) SetBit(blended[s], v);
    for (std::size_t t = s + 1; t < shapes; ++t) {
      terms.Pair(t, &cross);
      pair_runs_[s * shapes + t] = AppendTerms(cross, pair_deltas_);
      for (std::uint32_t v : cross.vertices) {
        SetBit(blended[s], v);  // each shape's set covers its pairs' vertices
        SetBit(blended[t], v);
      }
    }
  }
  for (const Bits& set : blended) blended_.push_back(AppendSpan(set, pool_));
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

BlendPlan::RunList BlendPlan::AppendTerms(const VertexTerms& terms, std::vector<glm::vec3>& deltas) {
  const RunList list = AppendRuns(terms.vertices, static_cast<std::uint32_t>(deltas.size()));
  deltas.insert(deltas.end(), terms.values.begin(), terms.values.end());
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
