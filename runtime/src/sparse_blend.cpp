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

}  // namespace

void SparseBlend::Run(const BlendJob& job) {
  SparseBlend blend(job);
  blend.CollectActiveSets();
  blend.Positions();
  switch (job.normal_mode) {
    case NormalMode::kNone: break;
    case NormalMode::kBlendDeltas: blend.BlendedNormals(); break;
    case NormalMode::kRecompute: ComputeVertexNormals(job.out_positions, job.rig->triangles(), job.out_normals); break;
    case NormalMode::kBlendRecomputedDeltas: blend.BlendedRecomputedNormals(); break;
  }
  blend.Remember();
}

SparseBlend::SparseBlend(const BlendJob& job)
    : job_(job),
      state_(*job.state),
      plan_(job.state->plan()),
      positions_(job.out_positions.data()),
      normals_(job.normal_mode == NormalMode::kNone ? nullptr : job.out_normals.data()),
      normals_known_(normals_ != nullptr && state_.normals_ == normals_ && state_.normal_mode_ == job.normal_mode) {}

// The active shapes; this frame's moved vertices and those whose normal is
// not at rest: unions over the active shapes.
void SparseBlend::CollectActiveSets() {
  const NormalMode mode = job_.normal_mode;
  std::fill(state_.next_moved_.begin(), state_.next_moved_.end(), 0);
  if (mode == NormalMode::kBlendRecomputedDeltas) std::fill(state_.next_shaded_.begin(), state_.next_shaded_.end(), 0);
  state_.active_count_ = 0;
  for (std::size_t s = 0; s < job_.weights.size(); ++s) {
    if (job_.weights[s] == 0.0f) continue;
    state_.active_[state_.active_count_++] = static_cast<std::uint32_t>(s);
    Or(plan_, plan_.moved(s), state_.next_moved_);
    if (mode == NormalMode::kBlendRecomputedDeltas) Or(plan_, plan_.blended(s), state_.next_shaded_);
  }
  if (mode == NormalMode::kBlendDeltas) state_.next_shaded_ = state_.next_moved_;  // same size: no allocation
}

// Back to the neutral where the last frame moved (everywhere when the
// buffer is not the last frame's; the rest already is), then the active
// shapes' deltas in shape order, each shape's in one sequential pass.
void SparseBlend::Positions() {
  const std::span<const glm::vec3> neutral = job_.rig->positions();
  if (state_.positions_ == positions_) {
    ForEachRun(state_.moved_, [&](std::size_t first, std::size_t count) { CopyRun(positions_, neutral, first, count); });
  } else {
    std::memcpy(positions_, neutral.data(), neutral.size_bytes());
  }
  for (std::size_t k = 0; k < state_.active_count_; ++k) {
    const std::uint32_t s = state_.active_[k];
    AddRuns(plan_.entry_runs(s), job_.rig->shape(s).position_deltas.data(), job_.weights[s], positions_);
  }
}

// The normals of last frame's set and not this one's go back to `rest`
// (all when the buffer is not last frame's); this frame's start from `base`.
void SparseBlend::RestoreNormals(std::span<const glm::vec3> rest, std::span<const glm::vec3> base) {
  const Bits& now = state_.next_shaded_;
  if (normals_known_) {
    ForEachRun(state_.shaded_, state_.shaded_, &now,
               [&](std::size_t first, std::size_t count) { CopyRun(normals_, rest, first, count); });
  } else {
    std::memcpy(normals_, rest.data(), rest.size_bytes());
  }
  ForEachRun(now, [&](std::size_t first, std::size_t count) { CopyRun(normals_, base, first, count); });
}

// kBlendDeltas: the rig's normal deltas on the rig's normals at the moved
// vertices, renormalised as the whole-mesh path does.
void SparseBlend::BlendedNormals() {
  RestoreNormals(plan_.rest_normals(NormalMode::kBlendDeltas), job_.rig->normals());
  for (std::size_t k = 0; k < state_.active_count_; ++k) {
    const std::uint32_t s = state_.active_[k];
    AddRuns(plan_.entry_runs(s), job_.rig->shape(s).normal_deltas.data(), job_.weights[s], normals_);
  }
  bits::ForEachBit(state_.next_shaded_, [&](std::size_t v) { blend::RenormaliseBlended(normals_[v]); });
}

// kBlendRecomputedDeltas: S0 + sum_s (w_s dS_s + (w_s^2 - w_s) Q_s) +
// sum_{s<t} w_s w_t Q_st, normalised, where this frame turns normals; the
// rest normal where only the last did.
void SparseBlend::BlendedRecomputedNormals() {
  RestoreNormals(plan_.rest_normals(NormalMode::kBlendRecomputedDeltas), plan_.rest_sums());
  for (std::size_t k = 0; k < state_.active_count_; ++k) {
    const std::uint32_t s = state_.active_[k];
    const float w = job_.weights[s];
    AddRuns(plan_.sum_runs(s), plan_.sum_deltas().data(), w, normals_);
    AddRuns(plan_.quadratic_runs(s), plan_.quadratic_deltas().data(), w * w - w, normals_);
    for (std::size_t later = k + 1; later < state_.active_count_; ++later) {
      const std::uint32_t t = state_.active_[later];
      AddRuns(plan_.pair_runs(s, t), plan_.pair_deltas().data(), w * job_.weights[t], normals_);
    }
  }
  ForEachRun(state_.next_shaded_,
             [&](std::size_t first, std::size_t count) { blend::NormaliseSums(normals_ + first, count); });
}

// This frame's sets become what the buffers hold (swaps: no allocation).
void SparseBlend::Remember() {
  std::swap(state_.moved_, state_.next_moved_);
  state_.positions_ = positions_;
  const NormalMode mode = job_.normal_mode;
  const bool sparse_normals = mode == NormalMode::kBlendDeltas || mode == NormalMode::kBlendRecomputedDeltas;
  if (sparse_normals) std::swap(state_.shaded_, state_.next_shaded_);
  state_.normals_ = sparse_normals ? normals_ : nullptr;  // kRecompute writes every normal anyway
  state_.normal_mode_ = mode;
}

}  // namespace facerig
