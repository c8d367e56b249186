#include "measure/dense_blend.h"

#include <catch2/catch.hpp>

#include "facerig/runtime/blend_job.h"
#include "support/test_meshes.h"

namespace {

// Max |sparse - dense| over all coordinates.
float CompareWithDense(const facerig::Rig& rig, const facerig::DenseBlendShapes& dense,
                       const std::vector<float>& weights) {
  std::vector<glm::vec3> positions(rig.vertex_count());
  facerig::BlendJob job{&rig, weights, facerig::NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == facerig::BlendJobError::kNone);
  Eigen::VectorXf reference;
  facerig::DenseBlend(dense, weights, reference);
  float worst = 0.0f;
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
    for (int c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(positions[v][c] - reference(static_cast<Eigen::Index>(3 * v) + c)));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("Sparse blend equals the dense reference on a grid", "[dense_blend]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(12, 6);
  const facerig::DenseBlendShapes dense = facerig::MakeDenseBlendShapes(rig);
  REQUIRE(dense.deltas.rows() == 3 * 144);
  REQUIRE(dense.deltas.cols() == 6);
  REQUIRE(CompareWithDense(rig, dense, {0.3f, 0.0f, 1.0f, 0.5f, 0.0f, 0.9f}) < 1e-6f);
  std::vector<float> wrong(5, 0.0f);
  Eigen::VectorXf out;
  REQUIRE_THROWS(facerig::DenseBlend(dense, wrong, out));
}

TEST_CASE("Sparse blend equals the dense reference on the ICT rig (shared data)",
          "[dense_blend][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const facerig::DenseBlendShapes dense = facerig::MakeDenseBlendShapes(rig);
  const float tolerance = 1e-5f * rig.bounding_diagonal();
  std::vector<float> weights(rig.shape_count(), 0.0f);
  weights[*rig.FindShape("jawOpen")] = 1.0f;
  REQUIRE(CompareWithDense(rig, dense, weights) < tolerance);
  for (const char* name : {"mouthClose", "mouthFunnel", "mouthPucker", "mouthSmile_L", "mouthSmile_R",
                           "mouthStretch_L", "mouthStretch_R", "mouthLowerDown_L", "mouthLowerDown_R",
                           "mouthUpperUp_L", "mouthUpperUp_R"}) {
    weights[*rig.FindShape(name)] = 0.6f;
  }
  REQUIRE(CompareWithDense(rig, dense, weights) < tolerance);
  for (std::size_t s = 0; s < weights.size(); ++s) weights[s] = static_cast<float>(s % 5) * 0.25f;
  REQUIRE(CompareWithDense(rig, dense, weights) < tolerance);
}
