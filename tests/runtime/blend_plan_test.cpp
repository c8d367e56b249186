// BlendJob with a BlendState (only what moves) against the whole-mesh path.
#include "facerig/runtime/blend_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/crowd_blend_job.h"
#include "facerig/runtime/rig_builder.h"
#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

using facerig::BlendJob;
using facerig::BlendJobError;
using facerig::BlendPlan;
using facerig::BlendState;
using facerig::NormalMode;

namespace {

constexpr int kGrid = 24;

// A bumpy grid whose shapes each move one 5x5 patch (with normal deltas):
// like a face's shapes, each reaches a small part of the mesh.
facerig::Rig MakePatchRig() {
  facerig::RawRig raw = facerig::test::MakeGridRawRig(kGrid, 0, false);
  for (std::size_t v = 0; v < raw.positions.size(); ++v) raw.positions[v].z = 0.3f * std::sin(0.7f * float(v));
  const int corners[][2] = {{2, 2}, {4, 3}, {15, 15}, {12, 2}, {2, 16}, {17, 8}};
  for (int s = 0; s < 6; ++s) {
    facerig::RawBlendShape shape;
    shape.name = "patch" + std::to_string(s);
    for (int y = corners[s][1]; y < corners[s][1] + 5; ++y) {
      for (int x = corners[s][0]; x < corners[s][0] + 5; ++x) {
        shape.vertex_indices.push_back(static_cast<std::uint32_t>(y * kGrid + x));
        const float t = 0.37f * float(x * 3 + y + s);
        shape.position_deltas.emplace_back(0.2f * std::sin(t), 0.1f * std::cos(t), 0.5f + 0.1f * float(s));
        shape.normal_deltas.emplace_back(0.05f * std::cos(t), 0.03f, -0.02f);
      }
    }
    raw.shapes.push_back(std::move(shape));
  }
  std::string problem;
  std::optional<facerig::Rig> rig = facerig::RigBuilder::Build(std::move(raw), &problem);
  if (!rig) FAIL(problem);
  return std::move(*rig);
}

// Degrees between two normals.
double Degrees(const glm::vec3& a, const glm::vec3& b) {
  const double cosine = glm::dot(glm::normalize(a), glm::normalize(b));
  return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

double WorstDegrees(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double worst = 0.0;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, Degrees(a[v], b[v]));
  return worst;
}

// Frame f's weights: shapes switch on and off, some frames have none.
std::vector<float> FrameWeights(std::size_t shapes, int frame) {
  std::vector<float> weights(shapes, 0.0f);
  std::uint32_t state = 2654435761u * static_cast<std::uint32_t>(frame + 1);
  for (std::size_t s = 0; s < shapes; ++s) {
    state = state * 1664525u + 1013904223u;
    if ((state >> 28) < 7) weights[s] = -0.5f + 2.0f * static_cast<float>(state >> 8) / float(1u << 24);
  }
  return weights;
}

bool SameBits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

struct Outputs {
  std::vector<glm::vec3> positions, normals;
  explicit Outputs(std::size_t n) : positions(n, glm::vec3(5.0f)), normals(n, glm::vec3(5.0f)) {}
};

// The whole-mesh path's outputs for these weights.
Outputs WholeMesh(const facerig::Rig& rig, const std::vector<float>& weights, NormalMode mode) {
  Outputs out(rig.vertex_count());
  BlendJob job{&rig, weights, mode, out.positions, out.normals};
  REQUIRE(job.Run() == BlendJobError::kNone);
  return out;
}

// A fresh state's first frame: every vertex written.
Outputs FromScratch(const BlendPlan& plan, const std::vector<float>& weights, NormalMode mode) {
  Outputs out(plan.rig().vertex_count());
  BlendState state(plan);
  BlendJob job{&plan.rig(), weights, mode, out.positions, out.normals, &state};
  REQUIRE(job.Run() == BlendJobError::kNone);
  return out;
}

}  // namespace

TEST_CASE("BlendJob with a state equals the whole-mesh path bit for bit, frame after frame", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  for (NormalMode mode : {NormalMode::kNone, NormalMode::kBlendDeltas, NormalMode::kRecompute}) {
    INFO("mode " << static_cast<int>(mode));
    BlendState state(plan);
    Outputs out(rig.vertex_count());
    bool some_sparse = false;
    for (int frame = 0; frame < 40; ++frame) {
      const std::vector<float> weights = FrameWeights(rig.shape_count(), frame);
      BlendJob job{&rig, weights, mode, out.positions, out.normals, &state};
      REQUIRE(job.Run() == BlendJobError::kNone);
      const Outputs expected = WholeMesh(rig, weights, mode);
      REQUIRE(SameBits(out.positions, expected.positions));
      if (mode != NormalMode::kNone) REQUIRE(SameBits(out.normals, expected.normals));
      const facerig::BlendWork work = state.LastWork();
      REQUIRE(work.moved_vertices < rig.vertex_count());
      some_sparse = some_sparse || (work.moved_vertices > 0 && work.moved_vertices < rig.vertex_count() / 2);
      if (mode == NormalMode::kBlendDeltas) REQUIRE(work.shaded_vertices == work.moved_vertices);
    }
    REQUIRE(some_sparse);
  }
}

TEST_CASE("BlendJob with a state writes only what moves", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  BlendState state(plan);
  Outputs out(rig.vertex_count());
  std::vector<float> weights(rig.shape_count(), 0.0f);
  weights[0] = 1.0f;
  BlendJob job{&rig, weights, NormalMode::kBlendRecomputedDeltas, out.positions, out.normals, &state};
  REQUIRE(job.Run() == BlendJobError::kNone);
  // Far from patches 0 and 2 (the corner opposite both): a marker that the
  // next frames must not overwrite.
  const std::size_t far = (kGrid - 1) * kGrid + kGrid - 1;
  out.positions[far] = glm::vec3(-7.0f);
  out.normals[far] = glm::vec3(-7.0f);
  weights[0] = 0.5f;
  weights[2] = 1.0f;
  REQUIRE(job.Run() == BlendJobError::kNone);
  REQUIRE(out.positions[far] == glm::vec3(-7.0f));
  REQUIRE(out.normals[far] == glm::vec3(-7.0f));
  REQUIRE(state.LastWork().moved_vertices == 2 * 25);
  // The moved patch did change, and a vertex next to it got its new normal.
  const Outputs expected = WholeMesh(rig, weights, NormalMode::kRecompute);
  const std::size_t in_patch2 = 17 * kGrid + 17, next_to_patch2 = 14 * kGrid + 16;
  REQUIRE(out.positions[in_patch2] == expected.positions[in_patch2]);
  REQUIRE(Degrees(out.normals[next_to_patch2], expected.normals[next_to_patch2]) < 0.5);
  REQUIRE(Degrees(out.normals[next_to_patch2], rig.normals()[next_to_patch2]) > 5.0);
  // Reset: the next frame writes every vertex again.
  state.Reset();
  REQUIRE(job.Run() == BlendJobError::kNone);
  REQUIRE(SameBits(out.positions, expected.positions));
  REQUIRE(out.normals[far] == expected.normals[far]);
}

TEST_CASE("Blended recomputed normals: one shape at any weight, and shapes together", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  // One shape alone: its normal sums are exactly quadratic in the weight, so
  // only what the plan left out (under 0.2 degree a shape for weights in
  // [0, 1], more when extrapolating) differs.
  for (float w : {0.3f, 0.7f, 1.0f, 1.6f, -0.4f}) {
    std::vector<float> weights(rig.shape_count(), 0.0f);
    weights[2] = w;
    const Outputs blended = FromScratch(plan, weights, NormalMode::kBlendRecomputedDeltas);
    const Outputs recomputed = WholeMesh(rig, weights, NormalMode::kRecompute);
    INFO("weight " << w);
    REQUIRE(SameBits(blended.positions, recomputed.positions));
    REQUIRE(WorstDegrees(blended.normals, recomputed.normals) < (w >= 0.0f && w <= 1.0f ? 0.5 : 1.5));
  }
  // Overlapping shapes: their cross term is kept too, so again only what the
  // plan left out differs (each term under 0.2 degree at weights 1/2).
  const std::vector<float> weights = {0.8f, 0.9f, 0.0f, 0.0f, 0.0f, 0.0f};
  const Outputs blended = FromScratch(plan, weights, NormalMode::kBlendRecomputedDeltas);
  const Outputs recomputed = WholeMesh(rig, weights, NormalMode::kRecompute);
  const double worst = WorstDegrees(blended.normals, recomputed.normals);
  REQUIRE(worst < 1.0);
  REQUIRE(worst > 0.0);  // not the recomputed path itself
  // Without a state there is nowhere to keep what moved.
  Outputs out(rig.vertex_count());
  BlendJob stateless{&rig, weights, NormalMode::kBlendRecomputedDeltas, out.positions, out.normals};
  REQUIRE(stateless.Run() == BlendJobError::kModeNeedsState);
}

TEST_CASE("A blend state follows mode changes, other buffers and extreme weights", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  BlendState state(plan);
  Outputs a(rig.vertex_count()), b(rig.vertex_count());
  const NormalMode modes[] = {NormalMode::kBlendRecomputedDeltas, NormalMode::kNone, NormalMode::kRecompute,
                              NormalMode::kBlendDeltas, NormalMode::kBlendRecomputedDeltas, NormalMode::kBlendDeltas};
  for (int frame = 0; frame < 36; ++frame) {
    const NormalMode mode = modes[frame % 6];
    Outputs& out = (frame / 6) % 2 ? b : a;  // one state, two pairs of buffers in turn
    std::vector<float> weights = FrameWeights(rig.shape_count(), frame);
    if (frame % 5 == 0) weights[1] = 1e6f;  // finite: accepted as today
    BlendJob job{&rig, weights, mode, out.positions, out.normals, &state};
    REQUIRE(job.Run() == BlendJobError::kNone);
    // Blended recomputed normals have no whole-mesh path: a fresh state's
    // first frame (every vertex written) is the reference.
    const Outputs expected = mode == NormalMode::kBlendRecomputedDeltas ? FromScratch(plan, weights, mode)
                                                                        : WholeMesh(rig, weights, mode);
    INFO("frame " << frame);
    REQUIRE(SameBits(out.positions, expected.positions));
    if (mode != NormalMode::kNone) REQUIRE(SameBits(out.normals, expected.normals));
  }
}

TEST_CASE("BlendJob refuses a state built for another rig and leaves the outputs", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const facerig::Rig other = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(other);
  BlendState state(plan);
  Outputs out(rig.vertex_count());
  const std::vector<float> weights(rig.shape_count(), 0.5f);
  BlendJob job{&rig, weights, NormalMode::kRecompute, out.positions, out.normals, &state};
  REQUIRE(job.Run() == BlendJobError::kStateForAnotherRig);
  for (const glm::vec3& p : out.positions) REQUIRE(p == glm::vec3(5.0f));
  REQUIRE(std::string(facerig::ToString(BlendJobError::kStateForAnotherRig)).find("another rig") != std::string::npos);
}

TEST_CASE("BlendJob with a state allocates nothing, in every normal mode", "[blend_job][allocation]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  for (NormalMode mode : {NormalMode::kNone, NormalMode::kBlendDeltas, NormalMode::kRecompute,
                          NormalMode::kBlendRecomputedDeltas}) {
    BlendState state(plan);
    Outputs out(rig.vertex_count());
    std::vector<float> weights(rig.shape_count(), 0.0f);
    BlendJob job{&rig, weights, mode, out.positions, out.normals, &state};
    facerig::test::AllocationCounter counter;
    for (int frame = 0; frame < 20; ++frame) {
      for (std::size_t s = 0; s < weights.size(); ++s) weights[s] = float((frame + s) % 3) * 0.4f;
      REQUIRE(job.Run() == BlendJobError::kNone);
    }
    state.Reset();
    REQUIRE(job.Run() == BlendJobError::kNone);
    REQUIRE(counter.count() == 0);
  }
}

TEST_CASE("BlendJob with a state: one state per character on many threads over one plan", "[blend_job][threads]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  constexpr int kThreads = 4;
  std::vector<Outputs> outputs(kThreads, Outputs(rig.vertex_count()));
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      BlendState state(plan);
      for (int frame = 0; frame < 100; ++frame) {
        const std::vector<float> weights = FrameWeights(rig.shape_count(), frame * kThreads + t);
        BlendJob job{&rig, weights, NormalMode::kBlendRecomputedDeltas, outputs[t].positions, outputs[t].normals,
                     &state};
        mismatches[t] += job.Run() != BlendJobError::kNone;
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    REQUIRE(mismatches[t] == 0);
    const Outputs expected =
        FromScratch(plan, FrameWeights(rig.shape_count(), 99 * kThreads + t), NormalMode::kBlendRecomputedDeltas);
    REQUIRE(SameBits(outputs[t].positions, expected.positions));
    REQUIRE(SameBits(outputs[t].normals, expected.normals));
  }
}

TEST_CASE("CrowdBlendJob equals each member's own BlendJob, frame after frame", "[blend_job]") {
  const facerig::Rig rig = MakePatchRig();
  const BlendPlan plan = BlendPlan::Build(rig);
  constexpr std::size_t kMembers = 5;
  for (NormalMode mode : {NormalMode::kNone, NormalMode::kBlendDeltas, NormalMode::kBlendRecomputedDeltas}) {
    INFO("mode " << static_cast<int>(mode));
    std::vector<BlendState> crowd_states(kMembers, BlendState(plan)), own_states = crowd_states;
    std::vector<Outputs> crowd(kMembers, Outputs(rig.vertex_count())), own = crowd;
    std::vector<std::vector<float>> weights(kMembers);
    std::vector<facerig::CrowdMember> members(kMembers);
    for (int frame = 0; frame < 12; ++frame) {
      for (std::size_t m = 0; m < kMembers; ++m) {
        weights[m] = FrameWeights(rig.shape_count(), frame * 7 + static_cast<int>(m));
        members[m] = {weights[m], crowd[m].positions, crowd[m].normals, &crowd_states[m]};
        BlendJob job{&rig, weights[m], mode, own[m].positions, own[m].normals, &own_states[m]};
        REQUIRE(job.Run() == BlendJobError::kNone);
      }
      facerig::test::AllocationCounter counter;
      REQUIRE(facerig::CrowdBlendJob{&rig, mode, members}.Run() == BlendJobError::kNone);
      REQUIRE(counter.count() == 0);
      for (std::size_t m = 0; m < kMembers; ++m) {
        REQUIRE(SameBits(crowd[m].positions, own[m].positions));
        if (mode != NormalMode::kNone) REQUIRE(SameBits(crowd[m].normals, own[m].normals));
      }
    }
  }
  // A bad member is named and nothing is written.
  std::vector<BlendState> states(2, BlendState(plan));
  Outputs a(rig.vertex_count()), b(rig.vertex_count());
  const std::vector<float> good(rig.shape_count(), 0.5f), bad(rig.shape_count() - 1, 0.5f);
  const std::vector<facerig::CrowdMember> members = {{good, a.positions, a.normals, &states[0]},
                                                      {bad, b.positions, b.normals, &states[1]}};
  std::size_t failed = 99;
  REQUIRE(facerig::CrowdBlendJob{&rig, NormalMode::kNone, members}.Run(&failed) == BlendJobError::kWeightCountMismatch);
  REQUIRE(failed == 1);
  REQUIRE(a.positions.front() == glm::vec3(5.0f));
  const std::vector<facerig::CrowdMember> stateless = {{good, a.positions, a.normals, nullptr}};
  REQUIRE(facerig::CrowdBlendJob{&rig, NormalMode::kNone, stateless}.Run(&failed) == BlendJobError::kModeNeedsState);
  REQUIRE(failed == 0);
}
