// What the sparse blend needs to write only what moves: BlendPlan is built
// once per rig (which vertices, normals and triangles each shape reaches, its
// deltas as runs of consecutive vertices, and each shape's change of the
// recomputed normals); BlendState is kept per pair of output buffers (one per
// character) and remembers which of their vertices are not at rest.
//
// With a state, BlendJob::Run restores only the vertices the previous frame
// moved and adds the active shapes' deltas run by run. Positions, and normals
// in kNone, kBlendDeltas and kRecompute, equal the whole-mesh path bit for bit
// (a test compares them); kBlendRecomputedDeltas needs a state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// A set of vertex or triangle indices as the bit words that are not all zero:
// word k of the set is words[k - first_word] for first_word <= k < first_word + count.
struct BitSpan {
  std::uint32_t first_word = 0;
  std::uint32_t word_count = 0;
  std::uint32_t offset = 0;  // into BlendPlan's word pool
};

// Deltas [first_delta, first_delta + count) apply to the consecutive vertices
// [first_vertex, first_vertex + count).
struct DeltaRun {
  std::uint32_t first_vertex = 0;
  std::uint32_t count = 0;
  std::uint32_t first_delta = 0;
};

class BlendPlan {
 public:
  // Allocates (once, here); `rig` must outlive the plan and stay unchanged.
  static BlendPlan Build(const Rig& rig);

  const Rig& rig() const { return *rig_; }
  std::size_t vertex_words() const { return vertex_words_; }
  std::size_t triangle_words() const { return triangle_words_; }

  // The vertices shape s moves (its sparse entries).
  BitSpan moved(std::size_t shape) const { return moved_[shape]; }
  // The vertices whose recomputed normal shape s can change: the corners of
  // every triangle with a moved vertex.
  BitSpan shaded(std::size_t shape) const { return shaded_[shape]; }
  // The triangles those normals sum: every triangle with a shaded corner.
  BitSpan triangles(std::size_t shape) const { return triangles_[shape]; }
  const std::uint64_t* words(const BitSpan& span) const { return pool_.data() + span.offset; }

  // Shape s's entries as runs; first_delta indexes its position_deltas (and
  // normal_deltas).
  std::span<const DeltaRun> entry_runs(std::size_t shape) const;
  // Shape s's change of the recomputed normals at weight 1, over its shaded
  // vertices: first_delta indexes recomputed_normal_deltas().
  std::span<const DeltaRun> shaded_runs(std::size_t shape) const;
  std::span<const glm::vec3> recomputed_normal_deltas() const { return recomputed_normal_deltas_; }

  // The normals of the neutral as each normal mode produces them: recomputed
  // from the positions (kRecompute, kBlendRecomputedDeltas), and the rig's
  // normals renormalised (kBlendDeltas; empty when the rig has no normal deltas).
  std::span<const glm::vec3> rest_normals(NormalMode mode) const;

 private:
  struct RunRange {
    std::uint32_t first = 0, count = 0;
  };

  const Rig* rig_ = nullptr;
  std::size_t vertex_words_ = 0, triangle_words_ = 0;
  std::vector<BitSpan> moved_, shaded_, triangles_;
  std::vector<std::uint64_t> pool_;
  std::vector<RunRange> entry_run_ranges_, shaded_run_ranges_;
  std::vector<DeltaRun> runs_;
  std::vector<glm::vec3> recomputed_normal_deltas_;
  std::vector<glm::vec3> recomputed_rest_normals_, renormalised_rest_normals_;
};

// What one BlendJob::Run with a state touched: for the benchmark and tests.
struct BlendWork {
  std::size_t moved_vertices = 0;   // positions not at rest
  std::size_t shaded_vertices = 0;  // normals not at rest
  std::size_t triangles = 0;        // triangle normals evaluated (kRecompute)
};

// The per-character part: which vertices of its output buffers are not at
// rest, and scratch bits for the next frame, all sized in the constructor.
// Keep one state per pair of output buffers, and let only BlendJob write into
// them; after writing into them yourself, call Reset().
class BlendState {
 public:
  // `plan` must outlive the state.
  explicit BlendState(const BlendPlan& plan);

  const BlendPlan& plan() const { return *plan_; }
  // The next Run writes every vertex (the buffers' contents are unknown).
  void Reset();
  // Counted from the bits the last Run left (popcounts: not per frame).
  BlendWork LastWork() const;

 private:
  friend class SparseBlend;

  const BlendPlan* plan_;
  // Where the last Run wrote, and in which normal mode; null: unknown.
  const glm::vec3* positions_ = nullptr;
  const glm::vec3* normals_ = nullptr;
  NormalMode normal_mode_ = NormalMode::kNone;
  // Vertices whose position / normal is not at rest in those buffers.
  std::vector<std::uint64_t> moved_, shaded_;
  // This frame's sets, built in Run (then swapped with the two above).
  std::vector<std::uint64_t> next_moved_, next_shaded_, next_triangles_;
};

}  // namespace facerig
