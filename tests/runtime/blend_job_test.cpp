#include "facerig/runtime/blend_job.h"

#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

using facerig::BlendJob;
using facerig::BlendJobError;
using facerig::NormalMode;

namespace {

// The per-vertex reference: a plain dense accumulation, independent of the job's loops.
std::vector<glm::vec3> ReferenceBlend(const facerig::Rig& rig, const std::vector<float>& weights) {
  std::vector<glm::vec3> out(rig.positions().begin(), rig.positions().end());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const facerig::BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      out[shape.vertex_indices[i]] += weights[s] * shape.position_deltas[i];
    }
  }
  return out;
}

float MaxDifference(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const glm::vec3 d = glm::abs(a[i] - b[i]);
    worst = std::max({worst, d.x, d.y, d.z});
  }
  return worst;
}

}  // namespace

TEST_CASE("BlendJob with zero weights gives the neutral", "[blend_job]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(8, 4);
  std::vector<float> weights(rig.shape_count(), 0.0f);
  std::vector<glm::vec3> positions(rig.vertex_count(), glm::vec3(99.0f));
  BlendJob job{&rig, weights, NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == BlendJobError::kNone);
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) REQUIRE(positions[v] == rig.positions()[v]);
}

TEST_CASE("BlendJob equals the dense reference on a grid", "[blend_job]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(10, 5);
  const std::vector<float> weights = {0.5f, 0.0f, 1.0f, -0.25f, 1.5f};
  std::vector<glm::vec3> positions(rig.vertex_count());
  BlendJob job{&rig, weights, NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == BlendJobError::kNone);
  REQUIRE(MaxDifference(positions, ReferenceBlend(rig, weights)) < 1e-6f);
  // Not just the neutral: the weights really moved vertices.
  REQUIRE(MaxDifference(positions, {rig.positions().begin(), rig.positions().end()}) > 0.1f);
}

TEST_CASE("BlendJob normals: blended deltas and recomputed", "[blend_job]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(6, 3, /*with_normal_deltas=*/true);
  const std::vector<float> weights = {1.0f, 0.0f, 0.5f};
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  BlendJob job{&rig, weights, NormalMode::kBlendDeltas, positions, normals};
  REQUIRE(job.Run() == BlendJobError::kNone);
  // Expected: neutral normal + weighted normal deltas, renormalised.
  std::vector<glm::vec3> expected(rig.normals().begin(), rig.normals().end());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const facerig::BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      expected[shape.vertex_indices[i]] += weights[s] * shape.normal_deltas[i];
    }
  }
  for (glm::vec3& n : expected) n = glm::normalize(n);
  REQUIRE(MaxDifference(normals, expected) < 1e-6f);

  job.normal_mode = NormalMode::kRecompute;
  REQUIRE(job.Run() == BlendJobError::kNone);
  std::vector<glm::vec3> recomputed(rig.vertex_count());
  facerig::ComputeVertexNormals(positions, rig.triangles(), recomputed);
  REQUIRE(MaxDifference(normals, recomputed) < 1e-6f);
  for (const glm::vec3& n : normals) REQUIRE(glm::length(n) == Approx(1.0f).margin(1e-5));
  // The grid is displaced out of plane, so the recomputed normals differ from the flat neutral's.
  REQUIRE(MaxDifference(normals, {rig.normals().begin(), rig.normals().end()}) > 0.01f);
}

TEST_CASE("BlendJob rejects invalid inputs without touching the outputs", "[blend_job]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(5, 2);
  std::vector<float> weights = {0.5f, 0.5f};
  std::vector<glm::vec3> positions(rig.vertex_count(), glm::vec3(7.0f));
  std::vector<glm::vec3> normals(rig.vertex_count(), glm::vec3(7.0f));
  BlendJob job{&rig, weights, NormalMode::kNone, positions, normals};
  REQUIRE(job.Validate() == BlendJobError::kNone);

  BlendJob no_rig = job;
  no_rig.rig = nullptr;
  REQUIRE(no_rig.Run() == BlendJobError::kNoRig);

  const std::vector<float> too_few = {0.5f};
  BlendJob short_weights = job;
  short_weights.weights = too_few;
  REQUIRE(short_weights.Run() == BlendJobError::kWeightCountMismatch);

  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    std::vector<float> bad_weights = {0.5f, bad};
    BlendJob non_finite = job;
    non_finite.weights = bad_weights;
    REQUIRE(non_finite.Run() == BlendJobError::kNonFiniteWeight);
  }

  BlendJob small_out = job;
  small_out.out_positions = std::span(positions).first(3);
  REQUIRE(small_out.Run() == BlendJobError::kPositionsTooSmall);

  BlendJob small_normals = job;
  small_normals.normal_mode = NormalMode::kRecompute;
  small_normals.out_normals = {};
  REQUIRE(small_normals.Run() == BlendJobError::kNormalsTooSmall);

  BlendJob no_deltas = job;
  no_deltas.normal_mode = NormalMode::kBlendDeltas;
  REQUIRE(no_deltas.Run() == BlendJobError::kRigHasNoNormalDeltas);

  for (const glm::vec3& p : positions) REQUIRE(p == glm::vec3(7.0f));
  for (const glm::vec3& n : normals) REQUIRE(n == glm::vec3(7.0f));
  REQUIRE(std::string(facerig::ToString(BlendJobError::kNonFiniteWeight)).find("NaN") != std::string::npos);
}

TEST_CASE("BlendJob::Run allocates nothing, in every normal mode", "[blend_job][allocation]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(16, 6, /*with_normal_deltas=*/true);
  std::vector<float> weights = {0.2f, 0.0f, 0.7f, 1.0f, 0.0f, 0.3f};
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  for (NormalMode mode : {NormalMode::kNone, NormalMode::kBlendDeltas, NormalMode::kRecompute}) {
    BlendJob job{&rig, weights, mode, positions, normals};
    facerig::test::AllocationCounter counter;
    for (int frame = 0; frame < 10; ++frame) {
      weights[0] = 0.1f * static_cast<float>(frame);
      REQUIRE(job.Run() == BlendJobError::kNone);
    }
    REQUIRE(counter.count() == 0);
  }
  // The counter itself works: a vector allocation is seen.
  facerig::test::AllocationCounter counter;
  std::vector<int> allocated(100);
  REQUIRE(counter.count() >= 1);
}

TEST_CASE("BlendJob: one job per character on many threads over one rig", "[blend_job][threads]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(32, 8, true);
  constexpr int kThreads = 4;
  std::vector<std::vector<float>> weights(kThreads, std::vector<float>(rig.shape_count()));
  std::vector<std::vector<glm::vec3>> positions(kThreads, std::vector<glm::vec3>(rig.vertex_count()));
  std::vector<std::vector<glm::vec3>> normals(kThreads, std::vector<glm::vec3>(rig.vertex_count()));
  for (int t = 0; t < kThreads; ++t) {
    for (std::size_t s = 0; s < rig.shape_count(); ++s) weights[t][s] = 0.1f * static_cast<float>((t + s) % 5);
  }
  std::vector<std::thread> threads;
  std::vector<int> failures(kThreads, 0);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      BlendJob job{&rig, weights[t], NormalMode::kBlendDeltas, positions[t], normals[t]};
      for (int frame = 0; frame < 200; ++frame) failures[t] += job.Run() != BlendJobError::kNone;
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    REQUIRE(failures[t] == 0);
    REQUIRE(MaxDifference(positions[t], ReferenceBlend(rig, weights[t])) < 1e-5f);
  }
}
