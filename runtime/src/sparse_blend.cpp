#include "sparse_blend.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "bit_runs.h"
#include "blend_kernels.h"
#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

using bits::ForEachRun;
using Bits = bits::Words;

void Or(const BlendPlan& plan, const BitSpan& span, Bits& into) {
  const std::uint64_t* from = plan.words(span);
  std::uint64_t* to = into.data() + span.first_word;
  for (std::uint32_t k = 0; k < span.word_count; ++k) to[k] |= from[k];
}

void AddRuns(std::span<const DeltaRun> runs, const glm::vec3* deltas, float w, glm::vec3* out) {
  for (const DeltaRun& run : runs) blend::AddRun(out + run.first_vertex, deltas + run.first_delta, run.count, w);
}

void CopyRun(glm::vec3* out, std::span<const glm::vec3> from, std::size_t first, std::size_t count) {
  std::memcpy(out + first, from.data() + first, count * sizeof(glm::vec3));
}

bool SparseNormals(NormalMode mode) {
  return mode == NormalMode::kBlendDeltas || mode == NormalMode::kBlendRecomputedDeltas;
}

constexpr std::size_t kTileWords = BlendPlan::kTileVertices / 64;

}  // namespace

void SparseBlend::Run(const Rig& rig, NormalMode mode, std::span<const CrowdMember> members) {
  for (const CrowdMember& member : members) Prepare(rig, mode, member);
  const std::size_t tiles = members.empty() ? 0 : members.front().state->plan().tile_count();
  for (std::size_t tile = 0; tile < tiles; ++tile) {
    for (const CrowdMember& member : members) {
      PositionsTile(rig, member, tile);
      if (SparseNormals(mode)) NormalsTile(rig, mode, member, tile);
    }
  }
  for (const CrowdMember& member : members) Finish(rig, mode, member);
}

// This frame's active shapes, the vertices they move and those whose normal
// they turn (unions over the active shapes); a buffer that is not the last
// frame's is reset to rest everywhere first.
void SparseBlend::Prepare(const Rig& rig, NormalMode mode, const CrowdMember& member) {
  BlendState& state = *member.state;
  const BlendPlan& plan = state.plan();
  std::fill(state.next_moved_.begin(), state.next_moved_.end(), 0);
  if (mode == NormalMode::kBlendRecomputedDeltas) std::fill(state.next_shaded_.begin(), state.next_shaded_.end(), 0);
  state.active_count_ = 0;
  for (std::size_t s = 0; s < member.weights.size(); ++s) {
    if (member.weights[s] == 0.0f) continue;
    state.active_[state.active_count_++] = static_cast<std::uint32_t>(s);
    Or(plan, plan.moved(s), state.next_moved_);
    if (mode == NormalMode::kBlendRecomputedDeltas) Or(plan, plan.blended(s), state.next_shaded_);
  }
  if (mode == NormalMode::kBlendDeltas) state.next_shaded_ = state.next_moved_;  // same size: no allocation

  if (state.positions_ != member.out_positions.data()) {
    std::memcpy(member.out_positions.data(), rig.positions().data(), rig.positions().size_bytes());
  }
  if (SparseNormals(mode) && (state.normals_ != member.out_normals.data() || state.normal_mode_ != mode)) {
    const std::span<const glm::vec3> rest = plan.rest_normals(mode);
    std::memcpy(member.out_normals.data(), rest.data(), rest.size_bytes());
  }
}

// Back to the neutral where the last frame or this one moves (the rest
// already is; after a reset the last frame's set is stale but at rest too),
// then the active shapes' deltas in shape order.
void SparseBlend::PositionsTile(const Rig& rig, const CrowdMember& member, std::size_t tile) {
  BlendState& state = *member.state;
  glm::vec3* positions = member.out_positions.data();
  const std::size_t first_word = tile * kTileWords, end_word = std::min(first_word + kTileWords, state.moved_.size());
  ForEachRun(state.moved_, state.next_moved_, nullptr, first_word, end_word,
             [&](std::size_t first, std::size_t count) { CopyRun(positions, rig.positions(), first, count); });
  for (std::size_t k = 0; k < state.active_count_; ++k) {
    const std::uint32_t s = state.active_[k];
    AddRuns(state.plan().entry_runs(s, tile), state.plan().position_deltas().data(), member.weights[s], positions);
  }
}

// The normals of this frame's set start from the base (the rig's normals for
// kBlendDeltas, the rest sums S0 for kBlendRecomputedDeltas) and take the
// active shapes' terms, then are normalised as the mode does; those of the
// last frame's set and not this one's go back to the rest normal.
void SparseBlend::NormalsTile(const Rig& rig, NormalMode mode, const CrowdMember& member, std::size_t tile) {
  BlendState& state = *member.state;
  const BlendPlan& plan = state.plan();
  glm::vec3* normals = member.out_normals.data();
  const Bits& now = state.next_shaded_;
  const std::size_t first_word = tile * kTileWords, end_word = std::min(first_word + kTileWords, now.size());
  const bool recomputed = mode == NormalMode::kBlendRecomputedDeltas;
  ForEachRun(state.shaded_, state.shaded_, &now, first_word, end_word,
             [&](std::size_t first, std::size_t count) { CopyRun(normals, plan.rest_normals(mode), first, count); });
  const std::span<const glm::vec3> base = recomputed ? plan.rest_sums() : rig.normals();
  ForEachRun(now, now, nullptr, first_word, end_word,
             [&](std::size_t first, std::size_t count) { CopyRun(normals, base, first, count); });
  for (std::size_t k = 0; k < state.active_count_; ++k) {
    const std::uint32_t s = state.active_[k];
    const float w = member.weights[s];
    if (!recomputed) {
      AddRuns(plan.entry_runs(s, tile), plan.normal_deltas().data(), w, normals);
      continue;
    }
    AddRuns(plan.sum_runs(s, tile), plan.sum_deltas().data(), w, normals);
    AddRuns(plan.quadratic_runs(s, tile), plan.quadratic_deltas().data(), w * w - w, normals);
    for (std::size_t later = k + 1; later < state.active_count_; ++later) {
      const std::uint32_t t = state.active_[later];
      AddRuns(plan.pair_runs(s, t, tile), plan.pair_deltas().data(), w * member.weights[t], normals);
    }
  }
  ForEachRun(now, now, nullptr, first_word, end_word, [&](std::size_t first, std::size_t count) {
    if (recomputed) {
      blend::NormaliseSums(normals + first, count);
    } else {
      for (std::size_t v = first; v < first + count; ++v) blend::RenormaliseBlended(normals[v]);
    }
  });
}

// kRecompute's normals (every vertex, as the whole-mesh path), and this
// frame's sets become what the buffers hold (swaps: no allocation).
void SparseBlend::Finish(const Rig& rig, NormalMode mode, const CrowdMember& member) {
  if (mode == NormalMode::kRecompute) ComputeVertexNormals(member.out_positions, rig.triangles(), member.out_normals);
  BlendState& state = *member.state;
  std::swap(state.moved_, state.next_moved_);
  state.positions_ = member.out_positions.data();
  if (SparseNormals(mode)) std::swap(state.shaded_, state.next_shaded_);
  state.normals_ = SparseNormals(mode) ? member.out_normals.data() : nullptr;
  state.normal_mode_ = mode;
}

}  // namespace facerig
