#include "facerig/offline/identity/caricature.h"

#include <cmath>
#include <random>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/io/obj.h"
#include "support/test_meshes.h"

namespace {

std::vector<glm::vec3> Blend(const facerig::Rig& rig, const std::vector<float>& weights) {
  std::vector<glm::vec3> positions(rig.vertex_count());
  facerig::BlendJob job{&rig, weights, facerig::NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == facerig::BlendJobError::kNone);
  return positions;
}

float MaxDistance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

}  // namespace

TEST_CASE("Average face, with and without rigid alignment", "[caricature]") {
  const std::vector<glm::vec3> a{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::vector<glm::vec3> b = a;
  b[3].z = 3.0f;
  const std::vector<std::vector<glm::vec3>> faces{a, b};
  const std::vector<glm::vec3> mean = facerig::AverageFace(faces, false);
  CHECK(mean[3] == glm::vec3(0.0f, 0.0f, 2.0f));
  // A face moved as a whole averages to the same face once aligned.
  std::vector<glm::vec3> shifted = a;
  for (glm::vec3& p : shifted) p += glm::vec3(5.0f, -2.0f, 1.0f);
  const std::vector<std::vector<glm::vec3>> same{a, shifted};
  CHECK(MaxDistance(facerig::AverageFace(same, true), a) < 1e-5f);
  CHECK_THROWS_AS(facerig::AverageFace({}, true), facerig::MeshInputError);
  const std::vector<std::vector<glm::vec3>> mismatched{a, {{0, 0, 0}}};
  CHECK_THROWS_AS(facerig::AverageFace(mismatched, true), facerig::MeshInputError);
}

TEST_CASE("Caricature factor: -1 the average, 0 the face, 3 four times the difference", "[caricature]") {
  const std::vector<glm::vec3> average{{0, 0, 0}, {1, 0, 0}};
  const std::vector<glm::vec3> face{{0, 1, 0}, {1, 0, 0.5f}};
  CHECK(facerig::Caricature(face, average, -1.0f) == average);
  CHECK(facerig::Caricature(face, average, 0.0f) == face);
  CHECK(facerig::Caricature(face, average, 3.0f)[0] == glm::vec3(0.0f, 4.0f, 0.0f));
  CHECK_THROWS_AS(facerig::Caricature(face, average, 3.5f), facerig::MeshInputError);
  CHECK_THROWS_AS(facerig::Caricature(face, average, -1.5f), facerig::MeshInputError);
  CHECK_THROWS_AS(facerig::Caricature(face, {}, 1.0f), facerig::MeshInputError);
}

TEST_CASE("A caricatured rig keeps its expressions", "[caricature]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(8, 3);
  std::vector<glm::vec3> average(rig.positions().begin(), rig.positions().end());
  for (glm::vec3& p : average) p.z -= 0.1f * std::sin(p.x);
  facerig::CaricatureParams params;
  params.factor = 2.0f;
  params.expressions = facerig::CaricatureExpressions::kKeepDeltas;
  std::optional<facerig::Rig> kept = facerig::RigBuilder::Build(facerig::CaricatureRig(rig, average, params));
  REQUIRE(kept.has_value());
  const std::vector<glm::vec3> neutral = facerig::Caricature(rig.positions(), average, 2.0f);
  CHECK(MaxDistance(kept->positions(), neutral) < 1e-6f);
  std::vector<float> weights(3, 0.0f);
  weights[1] = 1.0f;
  const std::vector<glm::vec3> original = Blend(rig, weights);
  const std::vector<glm::vec3> caricatured = Blend(*kept, weights);
  for (std::size_t v = 0; v < neutral.size(); ++v) {
    CHECK(glm::length((caricatured[v] - neutral[v]) - (original[v] - rig.positions()[v])) < 1e-5f);
  }
  params.expressions = facerig::CaricatureExpressions::kDeformationTransfer;
  params.transfer.anchor_vertices = {0};
  std::optional<facerig::Rig> transferred =
      facerig::RigBuilder::Build(facerig::CaricatureRig(rig, average, params));
  REQUIRE(transferred.has_value());
  CHECK(transferred->shape_count() == 3);
  CHECK(MaxDistance(transferred->positions(), neutral) < 1e-6f);
}

TEST_CASE("Identity morph blends the neutral while expressions keep working", "[caricature]") {
  const facerig::Rig template_rig = facerig::test::MakeGridRig(6, 2);
  std::vector<glm::vec3> target_neutral(template_rig.positions().begin(), template_rig.positions().end());
  for (glm::vec3& p : target_neutral) p = 1.3f * p + glm::vec3(0.0f, 0.0f, 0.2f * std::cos(p.y));
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  std::optional<facerig::Rig> target =
      facerig::RigBuilder::Build(facerig::TransferRig(template_rig, target_neutral, params));
  REQUIRE(target.has_value());
  std::optional<facerig::Rig> morph =
      facerig::RigBuilder::Build(facerig::IdentityMorphRig(template_rig, *target));
  REQUIRE(morph.has_value());
  REQUIRE(morph->shape_count() == 3);
  const std::size_t identity = *morph->FindShape(facerig::kIdentityMorphShape);
  CHECK(identity == 2);
  std::vector<float> weights(3, 0.0f);
  CHECK(MaxDistance(Blend(*morph, weights), template_rig.positions()) < 1e-6f);
  weights[identity] = 1.0f;
  CHECK(MaxDistance(Blend(*morph, weights), target->positions()) < 1e-5f);
  // At identity 1 every expression is the target rig's; half way, the neutral is half way.
  weights[0] = 1.0f;
  std::vector<float> target_weights{1.0f, 0.0f};
  CHECK(MaxDistance(Blend(*morph, weights), Blend(*target, target_weights)) < 1e-5f);
  weights = {0.0f, 0.0f, 0.5f};
  const std::vector<glm::vec3> half = Blend(*morph, weights);
  for (std::size_t v = 0; v < half.size(); ++v) {
    CHECK(glm::length(half[v] - 0.5f * (template_rig.positions()[v] + target->positions()[v])) < 1e-5f);
  }
  CHECK_THROWS_AS(facerig::IdentityMorphRig(*morph, *morph), facerig::MeshInputError);
  const facerig::Rig small = facerig::test::MakeGridRig(4, 1);
  CHECK_THROWS_AS(facerig::IdentityMorphRig(template_rig, small), facerig::MeshInputError);
}

TEST_CASE("Average and caricature of ICT identities (shared data)", "[caricature][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  std::vector<std::vector<glm::vec3>> faces;
  for (int k = 0; k < 4; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "identity%03d.obj", k);
    faces.push_back(facerig::ReadObj(facerig::test::IctDir() / name).positions);
  }
  const std::vector<glm::vec3> average = facerig::AverageFace(faces, false);
  // Each identity file is neutral + one mode: their mean is neutral + the mean mode.
  std::vector<glm::vec3> expected(rig.positions().begin(), rig.positions().end());
  for (std::size_t v = 0; v < expected.size(); ++v) {
    glm::vec3 sum(0.0f);
    for (const auto& face : faces) sum += face[v] - rig.positions()[v];
    expected[v] += 0.25f * sum;
  }
  CHECK(MaxDistance(average, expected) < 1e-4f);
  // Caricature of identity 0 with its expressions by deformation transfer.
  facerig::CaricatureParams params;
  params.factor = 1.5f;
  facerig::Rig face_rig = *facerig::RigBuilder::Build(
      facerig::TransferRig(rig, faces[0], params.transfer));
  std::optional<facerig::Rig> caricature =
      facerig::RigBuilder::Build(facerig::CaricatureRig(face_rig, average, params));
  REQUIRE(caricature.has_value());
  CHECK(caricature->shape_count() == 53);
  // Exaggerated: 2.5 times as far from the average as the face is.
  const std::size_t v = 100;
  CHECK(glm::length(caricature->positions()[v] - average[v]) ==
        Approx(2.5f * glm::length(faces[0][v] - average[v])).margin(1e-4));
}
