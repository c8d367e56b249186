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
  plan.tile_count_ = (rig.vertex_count() + kTileVertices - 1) / kTileVertices;
  // Adding +0 to a -0.0 gives +0.0: entry runs must not bridge such vertices.
  Bits negative_zero(plan.vertex_words_);
  const auto has_negative_zero = [](const glm::vec3& v) {
    return (v.x == 0.0f && std::signbit(v.x)) || (v.y == 0.0f && std::signbit(v.y)) || (v.z == 0.0f && std::signbit(v.z));
  };
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
    if (has_negative_zero(rig.positions()[v]) || (rig.has_normal_deltas() && has_negative_zero(rig.normals()[v]))) {
      SetBit(negative_zero, v);
    }
  }
  Bits moved(plan.vertex_words_);
  std::vector<std::int64_t> slots;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    std::fill(moved.begin(), moved.end(), 0);
    for (std::uint32_t v : shape.vertex_indices) SetBit(moved, v);
    plan.moved_.push_back(AppendSpan(moved, plan.pool_));
    plan.entry_runs_.push_back(plan.AppendRuns(shape.vertex_indices,
                                               static_cast<std::uint32_t>(plan.position_deltas_.size()), &negative_zero, slots));
    for (std::int64_t slot : slots) {
      const auto i = static_cast<std::size_t>(slot);
      plan.position_deltas_.push_back(slot < 0 ? glm::vec3(0.0f) : shape.position_deltas[i]);
      if (rig.has_normal_deltas()) plan.normal_deltas_.push_back(slot < 0 ? glm::vec3(0.0f) : shape.normal_deltas[i]);
    }
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
  Bits covered(vertex_words_);
  for (std::size_t s = 0; s < shapes; ++s) {
    terms.Select(s);
    terms.Single(&change, &quadratic);
    sum_runs_.push_back(AppendTerms(change, sum_deltas_, blended[s]));
    quadratic_runs_.push_back(AppendTerms(quadratic, quadratic_deltas_, blended[s]));
    for (std::size_t t = s + 1; t < shapes; ++t) {
      terms.Pair(t, &cross);
      std::fill(covered.begin(), covered.end(), 0);
      pair_runs_[s * shapes + t] = AppendTerms(cross, pair_deltas_, covered);
      for (std::size_t w = 0; w < covered.size(); ++w) {
        blended[s][w] |= covered[w];  // each shape's set covers its pairs' vertices
        blended[t][w] |= covered[w];
      }
    }
  }
  for (const Bits& set : blended) blended_.push_back(AppendSpan(set, pool_));
}

BlendPlan::RunList BlendPlan::AppendRuns(std::span<const std::uint32_t> vertices, std::uint32_t first_delta,
                                         const Bits* unbridgeable, std::vector<std::int64_t>& slots) {
  slots.clear();
  RunList list;
  list.first = static_cast<std::uint32_t>(runs_.size());
  if (vertices.empty()) return list;
  list.tile_table = static_cast<std::uint32_t>(tile_starts_.size());
  tile_starts_.push_back(0);
  const auto bridges = [&](std::uint32_t from, std::uint32_t to) {  // vertices from < to, both in the list
    if (to % kTileVertices == 0 || to / kTileVertices != from / kTileVertices || to - from - 1 > kMaxGap) return false;
    for (std::uint32_t v = from + 1; v < to; ++v) {
      if (unbridgeable != nullptr && bits::Test(*unbridgeable, v)) return false;
    }
    return true;
  };
  std::size_t tile = 0;  // the last tile whose start is known
  for (std::size_t i = 0; i < vertices.size();) {
    for (; tile < vertices[i] / kTileVertices; ++tile) {
      tile_starts_.push_back(static_cast<std::uint32_t>(runs_.size()) - list.first);
    }
    DeltaRun run{vertices[i], 0, first_delta + static_cast<std::uint32_t>(slots.size())};
    std::size_t end = i;
    do {
      for (std::uint32_t gap = end > i ? vertices[end - 1] + 1 : vertices[end]; gap < vertices[end]; ++gap) {
        slots.push_back(-1);
      }
      slots.push_back(static_cast<std::int64_t>(end));
      ++end;
    } while (end < vertices.size() && bridges(vertices[end - 1], vertices[end]));
    run.count = vertices[end - 1] - run.first_vertex + 1;
    runs_.push_back(run);
    i = end;
  }
  list.count = static_cast<std::uint32_t>(runs_.size()) - list.first;
  for (; tile < tile_count_; ++tile) tile_starts_.push_back(list.count);
  return list;
}

BlendPlan::RunList BlendPlan::AppendTerms(const VertexTerms& terms, std::vector<glm::vec3>& deltas, Bits& covered) {
  std::vector<std::int64_t> slots;
  const RunList list = AppendRuns(terms.vertices, static_cast<std::uint32_t>(deltas.size()), nullptr, slots);
  for (std::int64_t slot : slots) deltas.push_back(slot < 0 ? glm::vec3(0.0f) : terms.values[static_cast<std::size_t>(slot)]);
  for (const DeltaRun& run : Runs(list)) {
    for (std::uint32_t v = run.first_vertex; v < run.first_vertex + run.count; ++v) SetBit(covered, v);
  }
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
