#include "sparse_blend.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <utility>

#include "blend_kernels.h"
#include "facerig/runtime/blend_plan.h"

namespace facerig {
namespace {

using Bits = std::vector<std::uint64_t>;

// Calls f(index) for each index set in `a` or `b` and not in `except`, in
// increasing order (pass the same set twice, or an empty `except`, for fewer).
template <typename F>
inline void ForEachBit(const Bits& a, const Bits& b, const Bits* except, F&& f) {
  for (std::size_t w = 0; w < a.size(); ++w) {
    std::uint64_t word = a[w] | b[w];
    if (except != nullptr) word &= ~(*except)[w];
    for (; word != 0; word &= word - 1) f(w * 64 + static_cast<std::size_t>(std::countr_zero(word)));
  }
}
template <typename F>
inline void ForEachBit(const Bits& bits, F&& f) {
  ForEachBit(bits, bits, nullptr, f);
}

inline bool TestBit(const Bits& bits, std::size_t index) { return (bits[index / 64] >> (index % 64)) & 1u; }

void Or(const BlendPlan& plan, const BitSpan& span, Bits& into) {
  const std::uint64_t* from = plan.words(span);
  std::uint64_t* to = into.data() + span.first_word;
  for (std::uint32_t k = 0; k < span.word_count; ++k) to[k] |= from[k];
}

// out[v] += w * delta over each run, as floats: the same operations as the
// whole-mesh path's per-vertex ones, over contiguous memory.
inline void AddRuns(std::span<const DeltaRun> runs, const glm::vec3* deltas, float w, glm::vec3* out) {
  for (const DeltaRun& run : runs) {
    float* __restrict to = reinterpret_cast<float*>(out + run.first_vertex);
    const float* __restrict from = reinterpret_cast<const float*>(deltas + run.first_delta);
    const std::size_t floats = 3 * std::size_t{run.count};
    for (std::size_t i = 0; i < floats; ++i) to[i] += w * from[i];
  }
}

// kBlendDeltas and kBlendRecomputedDeltas: the normals of this frame's set
// start from `base` and take the active shapes' weighted deltas, then are
// renormalised; those of last frame's set and not this one's go back to `rest`.
template <typename DeltasOf>
void BlendNormalDeltas(const BlendJob& job, const Bits& last, const Bits& now, bool last_known,
                              std::span<const glm::vec3> rest, std::span<const glm::vec3> base,
                              glm::vec3* normals, DeltasOf&& deltas_of) {
  if (last_known) {
    ForEachBit(last, last, &now, [&](std::size_t v) { normals[v] = rest[v]; });
  } else {
    std::memcpy(normals, rest.data(), rest.size_bytes());
  }
  ForEachBit(now, [&](std::size_t v) { normals[v] = base[v]; });
  for (std::size_t s = 0; s < job.weights.size(); ++s) {
    if (job.weights[s] != 0.0f) deltas_of(s, job.weights[s]);
  }
  ForEachBit(now, [&](std::size_t v) { blend::RenormaliseBlended(normals[v]); });
}

}  // namespace

void SparseBlend::Run(const BlendJob& job) {
  SparseBlend blend(job);
  blend.CollectActiveSets();
  blend.RestorePositions();
  blend.AddPositionDeltas();
  switch (job.normal_mode) {
    case NormalMode::kNone: break;
    case NormalMode::kBlendDeltas: blend.BlendedNormals(); break;
    case NormalMode::kRecompute: blend.RecomputedNormals(); break;
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

// This frame's moved vertices, and the vertices whose normal they change
// (for kRecompute also the triangles those sum): unions over the active shapes.
void SparseBlend::CollectActiveSets() {
  const NormalMode mode = job_.normal_mode;
  const bool shaded = mode == NormalMode::kRecompute || mode == NormalMode::kBlendRecomputedDeltas;
  const bool triangles = mode == NormalMode::kRecompute;
  std::fill(state_.next_moved_.begin(), state_.next_moved_.end(), 0);
  if (shaded) std::fill(state_.next_shaded_.begin(), state_.next_shaded_.end(), 0);
  if (triangles) std::fill(state_.next_triangles_.begin(), state_.next_triangles_.end(), 0);
  for (std::size_t s = 0; s < job_.weights.size(); ++s) {
    if (job_.weights[s] == 0.0f) continue;
    Or(plan_, plan_.moved(s), state_.next_moved_);
    if (shaded) Or(plan_, plan_.shaded(s), state_.next_shaded_);
    if (triangles) Or(plan_, plan_.triangles(s), state_.next_triangles_);
  }
  if (mode == NormalMode::kBlendDeltas) state_.next_shaded_ = state_.next_moved_;  // same size: no allocation
}

// Back to the neutral where the last frame moved (everywhere when the
// buffer is not the last frame's); the rest already is.
void SparseBlend::RestorePositions() {
  const std::span<const glm::vec3> neutral = job_.rig->positions();
  if (state_.positions_ != positions_) {
    std::memcpy(positions_, neutral.data(), neutral.size_bytes());
    return;
  }
  ForEachBit(state_.moved_, [&](std::size_t v) { positions_[v] = neutral[v]; });
}

void SparseBlend::AddPositionDeltas() {
  for (std::size_t s = 0; s < job_.weights.size(); ++s) {
    const float w = job_.weights[s];
    if (w == 0.0f) continue;
    AddRuns(plan_.entry_runs(s), job_.rig->shape(s).position_deltas.data(), w, positions_);
  }
}

// kBlendDeltas: the rig's normal deltas, over the moved vertices.
void SparseBlend::BlendedNormals() {
  BlendNormalDeltas(job_, state_.shaded_, state_.next_shaded_, normals_known_,
                    plan_.rest_normals(NormalMode::kBlendDeltas), job_.rig->normals(), normals_,
                    [&](std::size_t s, float w) {
                      AddRuns(plan_.entry_runs(s), job_.rig->shape(s).normal_deltas.data(), w, normals_);
                    });
}

// kBlendRecomputedDeltas: the plan's deltas of the recomputed normals, over
// the shaded vertices.
void SparseBlend::BlendedRecomputedNormals() {
  const std::span<const glm::vec3> rest = plan_.rest_normals(NormalMode::kBlendRecomputedDeltas);
  BlendNormalDeltas(job_, state_.shaded_, state_.next_shaded_, normals_known_, rest, rest, normals_,
                    [&](std::size_t s, float w) {
                      AddRuns(plan_.shaded_runs(s), plan_.recomputed_normal_deltas().data(), w, normals_);
                    });
}

// kRecompute: the shaded vertices' normals summed over their triangles in
// triangle order (as ComputeVertexNormals does, so the same bits); the
// vertices shaded last frame and not now go back to the rest normal.
void SparseBlend::RecomputedNormals() {
  const std::span<const glm::vec3> rest = plan_.rest_normals(NormalMode::kRecompute);
  const Bits& shaded = state_.next_shaded_;
  if (normals_known_) {
    ForEachBit(state_.shaded_, state_.shaded_, &shaded, [&](std::size_t v) { normals_[v] = rest[v]; });
  } else {
    std::memcpy(normals_, rest.data(), rest.size_bytes());
  }
  ForEachBit(shaded, [&](std::size_t v) { normals_[v] = glm::vec3(0.0f); });
  const std::span<const Triangle> triangles = job_.rig->triangles();
  ForEachBit(state_.next_triangles_, [&](std::size_t t) {
    const Triangle& triangle = triangles[t];
    const glm::vec3 n = blend::TriangleNormal(positions_, triangle);
    for (std::uint32_t corner : triangle) {
      if (TestBit(shaded, corner)) normals_[corner] += n;
    }
  });
  ForEachBit(shaded, [&](std::size_t v) { blend::NormaliseSum(normals_[v]); });
}

// This frame's sets become what the buffers hold (swaps: no allocation).
void SparseBlend::Remember() {
  std::swap(state_.moved_, state_.next_moved_);
  state_.positions_ = positions_;
  if (normals_ != nullptr) std::swap(state_.shaded_, state_.next_shaded_);
  state_.normals_ = normals_;
  state_.normal_mode_ = job_.normal_mode;
}

}  // namespace facerig
