// What the sparse blend needs to write only what moves: BlendPlan is built
// once per rig (which vertices each shape moves, its deltas as runs of
// consecutive vertices, and each shape's change of the recomputed normals);
// BlendState is kept per pair of output buffers (one per character) and
// remembers which of their vertices are not at rest.
//
// With a state, BlendJob::Run restores only the vertices the previous frame
// moved and adds the active shapes' deltas run by run: positions, and the
// normals of kBlendDeltas and kRecompute, equal the whole-mesh path's bit for
// bit (kRecompute still recomputes every normal). kBlendRecomputedDeltas
// needs a state: it blends the plan's normal changes over only the vertices
// whose normal turns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/rig.h"

namespace facerig {

struct VertexTerms;

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

  // The vertices shape s moves (its sparse entries).
  BitSpan moved(std::size_t shape) const { return moved_[shape]; }
  const std::uint64_t* words(const BitSpan& span) const { return pool_.data() + span.offset; }

  // The blend walks the mesh tile by tile, each tile for every character of
  // a crowd before the next, so that the tile's deltas stay in the cache. No
  // run crosses a tile boundary.
  static constexpr std::size_t kTileVertices = 2048;
  std::size_t tile_count() const { return tile_count_; }

  // Runs bridge gaps of up to kMaxGap vertices with zero deltas (adding +0
  // leaves a value's bits as they are, except -0.0: entry runs never bridge a
  // vertex with a -0.0 coordinate), so that there are fewer and longer runs.
  static constexpr std::uint32_t kMaxGap = 8;

  // Shape s's entries as runs (all, or one tile's); first_delta indexes
  // position_deltas() (and normal_deltas(), for a rig with normal deltas).
  std::span<const DeltaRun> entry_runs(std::size_t shape) const { return Runs(entry_runs_[shape]); }
  std::span<const DeltaRun> entry_runs(std::size_t shape, std::size_t tile) const {
    return Runs(entry_runs_[shape], tile);
  }
  std::span<const glm::vec3> position_deltas() const { return position_deltas_; }
  std::span<const glm::vec3> normal_deltas() const { return normal_deltas_; }

  // kBlendRecomputedDeltas. A vertex's recomputed normal is its normalised
  // sum S of triangle normals, which is exactly quadratic in the weights:
  //   S = S0 + sum_s (w_s dS_s + (w_s^2 - w_s) Q_s) + sum_{s<t} w_s w_t Q_st
  // (dS_s: shape s's change at weight 1; Q_s, Q_st: its quadratic and cross
  // terms). The plan keeps each term where it turns the normal by more than
  // kNormalTolerance radians (Q_s and Q_st at weights 1/2), and the blend sums
  // what the active shapes and their pairs keep, then normalises.
  // About 0.2 degree: at 0.3 the terms left out added up to more than a
  // degree on a few speech frames of the built-in head (benchmarks.md#crowd).
  static constexpr float kNormalTolerance = 0.0035f;
  // The vertices whose normal shape s turns, alone or with another shape;
  // its runs index sum_deltas(), quadratic_deltas() and pair_deltas().
  BitSpan blended(std::size_t shape) const { return blended_[shape]; }
  std::span<const DeltaRun> sum_runs(std::size_t shape) const { return Runs(sum_runs_[shape]); }
  std::span<const DeltaRun> sum_runs(std::size_t shape, std::size_t tile) const { return Runs(sum_runs_[shape], tile); }
  std::span<const DeltaRun> quadratic_runs(std::size_t shape) const { return Runs(quadratic_runs_[shape]); }
  std::span<const DeltaRun> quadratic_runs(std::size_t shape, std::size_t tile) const {
    return Runs(quadratic_runs_[shape], tile);
  }
  // Q_st of shapes s < t (empty where they share no triangle).
  std::span<const DeltaRun> pair_runs(std::size_t s, std::size_t t) const {
    return Runs(pair_runs_[s * rig_->shape_count() + t]);
  }
  std::span<const DeltaRun> pair_runs(std::size_t s, std::size_t t, std::size_t tile) const {
    return Runs(pair_runs_[s * rig_->shape_count() + t], tile);
  }
  std::span<const glm::vec3> sum_deltas() const { return sum_deltas_; }
  std::span<const glm::vec3> quadratic_deltas() const { return quadratic_deltas_; }
  std::span<const glm::vec3> pair_deltas() const { return pair_deltas_; }
  // S0: the neutral's triangle normal sums (not normalised).
  std::span<const glm::vec3> rest_sums() const { return rest_sums_; }

  // The normals of the neutral as each normal mode produces them: recomputed
  // from the positions (kBlendRecomputedDeltas), and the rig's
  // normals renormalised (kBlendDeltas; empty when the rig has no normal deltas).
  std::span<const glm::vec3> rest_normals(NormalMode mode) const;

 private:
  // One shape's runs: runs_[first, first + count); those of tile t start at
  // first + tile_starts_[tile_table + t] (tile_count_ + 1 entries; none when
  // the list is empty).
  struct RunList {
    std::uint32_t first = 0, count = 0, tile_table = 0;
  };
  std::span<const DeltaRun> Runs(const RunList& list) const { return std::span(runs_).subspan(list.first, list.count); }
  std::span<const DeltaRun> Runs(const RunList& list, std::size_t tile) const {
    if (list.count == 0) return {};
    const std::uint32_t begin = tile_starts_[list.tile_table + tile], end = tile_starts_[list.tile_table + tile + 1];
    return std::span(runs_).subspan(list.first + begin, end - begin);
  }
  // Runs over the increasing `vertices`, bridging gaps without a vertex in
  // `unbridgeable` (null: any); deltas numbered from `first_delta`. `slots`
  // gets each delta's index into `vertices`, or -1 for a bridged gap.
  RunList AppendRuns(std::span<const std::uint32_t> vertices, std::uint32_t first_delta,
                     const std::vector<std::uint64_t>* unbridgeable, std::vector<std::int64_t>& slots);
  // Runs over `terms`, their values appended to `deltas`; the vertices they
  // cover (bridged gaps too) set in `covered`.
  RunList AppendTerms(const VertexTerms& terms, std::vector<glm::vec3>& deltas, std::vector<std::uint64_t>& covered);
  // The kBlendRecomputedDeltas terms, and the blended() sets.
  void BuildNormalTerms();

  const Rig* rig_ = nullptr;
  std::size_t vertex_words_ = 0, tile_count_ = 0;
  std::vector<BitSpan> moved_, blended_;
  std::vector<std::uint64_t> pool_;
  std::vector<RunList> entry_runs_, sum_runs_, quadratic_runs_, pair_runs_;
  std::vector<DeltaRun> runs_;
  std::vector<std::uint32_t> tile_starts_;
  std::vector<glm::vec3> position_deltas_, normal_deltas_;
  std::vector<glm::vec3> sum_deltas_, quadratic_deltas_, pair_deltas_, rest_sums_;
  std::vector<glm::vec3> recomputed_rest_normals_, renormalised_rest_normals_;
};

// What one BlendJob::Run with a state touched: for the benchmark and tests.
struct BlendWork {
  std::size_t moved_vertices = 0;   // positions not at rest
  std::size_t shaded_vertices = 0;  // normals not at rest (kBlendDeltas, kBlendRecomputedDeltas)
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
  std::vector<std::uint64_t> next_moved_, next_shaded_;
  // This frame's shapes with a non-zero weight (the first active_count_).
  std::vector<std::uint32_t> active_;
  std::size_t active_count_ = 0;
};

}  // namespace facerig
