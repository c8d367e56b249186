#include "facerig/offline/transfer/displacement_transfer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/obj.h"
#include "measure/expression_error.h"
#include "facerig/offline/geometry/stats.h"
#include "support/test_meshes.h"

namespace {

facerig::DisplacementMatrices SmallMatrices() {
  facerig::DisplacementMatrices m;
  m.vertex_count = 3;
  m.base_extent = {2.0f, 1.0f, 0.5f};
  m.names = {"open", "smile"};
  m.displacements = {{{0.0f, -1.0f, 0.0f}, {0.0f, -0.5f, 0.0f}, {0.0f, 0.0f, 0.0f}},
                     {{0.5f, 0.25f, 0.0f}, {0.0f, 0.0f, 0.0f}, {-0.5f, 0.25f, 0.125f}}};
  return m;
}

std::vector<std::byte> Bytes(const std::filesystem::path& path) { return facerig::ReadFileBytes(path); }

void WriteBytes(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  facerig::WriteFileAtomically(path, bytes);
}

facerig::IoErrorKind ReadKind(const std::filesystem::path& path) {
  try {
    facerig::ReadDisplacementMatrices(path);
  } catch (const facerig::IoError& error) {
    return error.kind();
  }
  FAIL("no IoError");
  return facerig::IoErrorKind::kParse;
}

}  // namespace

TEST_CASE("Displacement matrices: per pose, after rigid alignment", "[displacement_transfer]") {
  const std::vector<glm::vec3> neutral{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {2, 0, 1}};
  // The pose moves vertex 4 and is also rotated and shifted as a whole.
  std::vector<glm::vec3> pose = neutral;
  pose[4] += glm::vec3(0.0f, 0.3f, 0.0f);
  const float c = std::cos(0.2f);
  const float s = std::sin(0.2f);
  for (glm::vec3& p : pose) p = glm::vec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z) + glm::vec3(1, 2, 3);
  const std::vector<std::vector<glm::vec3>> poses{pose};
  const std::vector<std::string> names{"raise"};
  facerig::DisplacementParams params;
  params.alignment_vertices = {0, 1, 2, 3, 5};
  const facerig::DisplacementMatrices m = facerig::ComputeDisplacementMatrices(neutral, poses, names, params);
  REQUIRE(m.displacements.size() == 1);
  for (std::size_t v = 0; v < neutral.size(); ++v) {
    const glm::vec3 expected = v == 4 ? glm::vec3(0.0f, 0.3f, 0.0f) : glm::vec3(0.0f);
    CHECK(glm::length(m.displacements[0][v] - expected) < 1e-5f);
  }
  CHECK(m.base_extent == glm::vec3(2.0f, 1.0f, 1.0f));
  const std::vector<std::string> two_names{"a", "b"};
  CHECK_THROWS_AS(facerig::ComputeDisplacementMatrices(neutral, poses, two_names),
                  facerig::MeshInputError);
}

TEST_CASE("Bounding-box transfer scales displacements with the face", "[displacement_transfer]") {
  const facerig::DisplacementMatrices m = SmallMatrices();
  // A model twice as wide and tall as the base (extents 4, 2, 1).
  const std::vector<glm::vec3> model{{0, 0, 0}, {4, 2, 0}, {1, 1, 1}};
  const facerig::DisplacementTransferResult r = facerig::TransferDisplacements(m, model);
  CHECK(r.scale == glm::vec3(2.0f, 2.0f, 2.0f));
  CHECK(glm::length(r.poses[0][0] - glm::vec3(0.0f, -2.0f, 0.0f)) < 1e-6f);
  CHECK(glm::length(r.poses[1][2] - (model[2] + glm::vec3(-1.0f, 0.5f, 0.25f))) < 1e-6f);
  facerig::DisplacementTransferParams raw;
  raw.normalize_by_bounding_box = false;
  CHECK(facerig::TransferDisplacements(m, model, raw).poses[0][0] == glm::vec3(0.0f, -1.0f, 0.0f));
  const std::vector<glm::vec3> wrong{{0, 0, 0}};
  CHECK_THROWS_AS(facerig::TransferDisplacements(m, wrong), facerig::MeshInputError);
}

TEST_CASE("A rotated model gets rotated displacements", "[displacement_transfer]") {
  const std::vector<glm::vec3> base{{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 0.5f}};
  std::vector<glm::vec3> moved = base;
  moved[1].y += 0.4f;
  const std::vector<std::vector<glm::vec3>> poses{moved};
  const std::vector<std::string> names{"p"};
  facerig::DisplacementParams no_align;
  no_align.rigid_align = false;
  const facerig::DisplacementMatrices m = facerig::ComputeDisplacementMatrices(base, poses, names, no_align);
  // The model: the base turned 90 degrees about z (x -> y).
  std::vector<glm::vec3> model;
  for (const glm::vec3& p : base) model.emplace_back(-p.y, p.x, p.z);
  facerig::DisplacementTransferParams params;
  params.base_neutral = base;
  const facerig::DisplacementTransferResult r = facerig::TransferDisplacements(m, model, params);
  CHECK(r.model_to_base_rms < 1e-5);
  CHECK(glm::length(r.scale - glm::vec3(1.0f)) < 1e-5f);
  CHECK(glm::length(r.poses[0][1] - (model[1] + glm::vec3(-0.4f, 0.0f, 0.0f))) < 1e-5f);
}

TEST_CASE("Combining poses is linear", "[displacement_transfer]") {
  const facerig::DisplacementMatrices m = SmallMatrices();
  const std::vector<float> weights{0.5f, 2.0f};
  const std::vector<glm::vec3> combined = facerig::CombinePoses(m, weights);
  CHECK(combined[0] == glm::vec3(1.0f, 0.0f, 0.0f));
  CHECK(combined[2] == glm::vec3(-1.0f, 0.5f, 0.25f));
  const std::vector<float> one{1.0f};
  CHECK_THROWS_AS(facerig::CombinePoses(m, one), facerig::MeshInputError);
}

TEST_CASE("Displacement-matrix files round-trip and refuse bad input", "[displacement_transfer]") {
  const facerig::DisplacementMatrices m = SmallMatrices();
  const std::filesystem::path path = facerig::test::OutputPath("small.fdm");
  facerig::WriteDisplacementMatrices(path, m);
  const facerig::DisplacementMatrices back = facerig::ReadDisplacementMatrices(path);
  CHECK(back.names == m.names);
  CHECK(back.displacements == m.displacements);
  CHECK(back.base_extent == m.base_extent);
  CHECK(back.vertex_count == 3);

  const std::vector<std::byte> good = Bytes(path);
  const std::filesystem::path bad = facerig::test::OutputPath("bad.fdm");
  std::vector<std::byte> bytes = good;
  bytes[0] = std::byte{'X'};
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kBadMagic);
  bytes = good;
  bytes[4] = std::byte{2};
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kUnsupportedVersion);
  bytes.assign(good.begin(), good.end() - 20);
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kTruncated);
  bytes = good;
  bytes[40] ^= std::byte{0x01};  // inside the first pose's displacements
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kChecksumMismatch);
  bytes = good;
  bytes[12] = std::byte{0xff};  // pose count 255: cannot fit
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kAbsurdCount);
  bytes = good;
  bytes.push_back(std::byte{0});
  WriteBytes(bad, bytes);
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kParse);
  WriteBytes(bad, {});
  CHECK(ReadKind(bad) == facerig::IoErrorKind::kEmpty);
  CHECK(ReadKind(facerig::test::OutputPath("missing.fdm")) == facerig::IoErrorKind::kOpenFailed);

  // A failed write leaves the previous file untouched.
  facerig::DisplacementMatrices broken = m;
  broken.displacements[1][2].x = std::nanf("");
  CHECK_THROWS_AS(facerig::WriteDisplacementMatrices(path, broken), facerig::IoError);
  CHECK(Bytes(path) == good);
  CHECK_THROWS_AS(facerig::WriteDisplacementMatrices(path / "not_a_dir" / "x.fdm", m), facerig::IoError);
}

TEST_CASE("Displacement transfer of the ICT rig onto a random identity (shared data)",
          "[displacement_transfer][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const facerig::DisplacementMatrices m = facerig::ComputeDisplacementMatrices(rig);
  REQUIRE(m.displacements.size() == 53);
  // Random identity: neutral + sum_i w_i (identity_i - neutral).
  std::mt19937 rng(5);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<glm::vec3> face(rig.positions().begin(), rig.positions().end());
  for (int k = 0; k < 20; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "identity%03d.obj", k);
    const std::vector<glm::vec3> identity = facerig::ReadObj(facerig::test::IctDir() / name).positions;
    const float w = normal(rng);
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += w * (identity[v] - rig.positions()[v]);
  }
  facerig::DisplacementTransferParams params;
  params.base_neutral.assign(rig.positions().begin(), rig.positions().end());
  params.align_model = false;  // ICT identities share the template's frame
  params.normalize_by_bounding_box = false;
  const facerig::DisplacementTransferResult raw = facerig::TransferDisplacements(m, face, params);
  params.normalize_by_bounding_box = true;
  const facerig::DisplacementTransferResult boxed = facerig::TransferDisplacements(m, face, params);
  std::vector<double> raw_errors;
  std::vector<double> boxed_errors;
  for (std::size_t s = 0; s < 53; ++s) {
    std::vector<glm::vec3> truth = face;
    for (std::size_t v = 0; v < face.size(); ++v) truth[v] += m.displacements[s][v];
    raw_errors.push_back(facerig::MeasureExpressionError(face, truth, raw.poses[s], 0, 9409).relative_error);
    boxed_errors.push_back(facerig::MeasureExpressionError(face, truth, boxed.poses[s], 0, 9409).relative_error);
  }
  WARN("displacement: median " << facerig::Percentile(raw_errors, 0.5) << " (bounding-box normalised: "
                               << facerig::Percentile(boxed_errors, 0.5) << ", scale " << boxed.scale.x
                               << " " << boxed.scale.y << " " << boxed.scale.z << ")");
  CHECK(facerig::Percentile(raw_errors, 1.0) <= 0.01);
  // The box ratio rescales by the face's size difference, which the additive ground truth lacks.
  CHECK(facerig::Percentile(boxed_errors, 0.5) <=
        1.5 * std::max({std::abs(boxed.scale.x - 1.0f), std::abs(boxed.scale.y - 1.0f),
                        std::abs(boxed.scale.z - 1.0f)}) + 0.01);
}
