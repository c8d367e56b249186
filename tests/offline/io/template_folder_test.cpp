#include "facerig/offline/io/template_folder.h"

#include <fstream>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "support/test_meshes.h"

namespace fs = std::filesystem;
using facerig::IoError;
using facerig::IoErrorKind;

namespace {

// A folder with a 4x4 grid neutral and two expressions that move vertices.
fs::path MakeGridTemplateFolder(const std::string& name) {
  const fs::path folder = facerig::test::OutputPath(name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  const facerig::Rig rig = facerig::test::MakeGridRig(4, 0);
  facerig::WriteObj(folder / "neutral.obj", rig);
  std::vector<glm::vec3> moved(rig.positions().begin(), rig.positions().end());
  moved[5].z += 0.5f;
  facerig::WriteObj(folder / "smile.obj", moved, {}, {}, rig.triangles(), rig.parts());
  moved[6].x -= 0.25f;
  facerig::WriteObj(folder / "frown.obj", moved, {}, {}, rig.triangles(), rig.parts());
  return folder;
}

}  // namespace

TEST_CASE("Template folder: expressions by glob, sparse deltas, units guessed", "[template_folder]") {
  const fs::path folder = MakeGridTemplateFolder("grid_template");
  facerig::TemplateImportReport report;
  const facerig::Rig rig = facerig::ImportTemplateFolder(folder, {}, &report);
  REQUIRE(rig.shape_count() == 2);
  REQUIRE(rig.shape_name(0) == "frown");  // sorted by name
  REQUIRE(rig.shape_name(1) == "smile");
  const facerig::BlendShapeView smile = rig.shape(1);
  REQUIRE(smile.vertex_indices.size() == 1);
  REQUIRE(smile.vertex_indices[0] == 5u);
  REQUIRE(smile.position_deltas[0].z == Approx(0.5f));
  REQUIRE(rig.shape(0).vertex_indices.size() == 2);
  // A 3 x 3 unit grid is 4.2 units across: too small for cm, mm or m head sizes.
  REQUIRE(report.units == facerig::Units::kUnknown);
  REQUIRE(report.drop_threshold == Approx(1e-6f * rig.bounding_diagonal()));

  facerig::TemplateImportOptions only_smile;
  only_smile.shape_names = {"smile"};
  only_smile.units = facerig::Units::kMillimetres;
  const facerig::Rig one = facerig::ImportTemplateFolder(folder, only_smile);
  REQUIRE(one.shape_count() == 1);
  REQUIRE(one.units() == facerig::Units::kMillimetres);

  facerig::TemplateImportOptions by_glob;
  by_glob.glob = "fr*.obj";
  REQUIRE(facerig::ImportTemplateFolder(folder, by_glob).shape_count() == 1);
}

TEST_CASE("Template folder: an explicit glob wins over vertex_indices.json, which wins over every *.obj",
          "[template_folder]") {
  const fs::path folder = MakeGridTemplateFolder("grid_template_listed");
  std::ofstream(folder / "vertex_indices.json") << R"({"expressions": ["smile"]})";
  const facerig::Rig listed = facerig::ImportTemplateFolder(folder);
  REQUIRE(listed.shape_count() == 1);
  CHECK(listed.shape_name(0) == "smile");
  facerig::TemplateImportOptions by_glob;
  by_glob.glob = "fr*.obj";  // was silently ignored when the folder lists its expressions
  const facerig::Rig globbed = facerig::ImportTemplateFolder(folder, by_glob);
  REQUIRE(globbed.shape_count() == 1);
  CHECK(globbed.shape_name(0) == "frown");
}

TEST_CASE("Template folder: errors name the offending file", "[template_folder][malformed]") {
  const fs::path folder = MakeGridTemplateFolder("grid_template_bad");
  // An expression with a different topology.
  const facerig::Rig other = facerig::test::MakeGridRig(5, 0);
  facerig::WriteObj(folder / "wrong.obj", other);
  try {
    facerig::ImportTemplateFolder(folder);
    FAIL("no error");
  } catch (const IoError& error) {
    REQUIRE(error.kind() == IoErrorKind::kTopologyMismatch);
    REQUIRE(error.path().find("wrong.obj") != std::string::npos);
  }
  // Same vertex count, different faces.
  const facerig::Rig grid = facerig::test::MakeGridRig(4, 0);
  std::vector<facerig::Triangle> flipped(grid.triangles().begin(), grid.triangles().end());
  std::swap(flipped[0][1], flipped[0][2]);
  facerig::WriteObj(folder / "wrong.obj", grid.positions(), {}, {}, flipped, grid.parts());
  REQUIRE_THROWS_AS(facerig::ImportTemplateFolder(folder), IoError);

  facerig::TemplateImportOptions missing;
  missing.shape_names = {"smile", "absent"};
  try {
    facerig::ImportTemplateFolder(folder, missing);
    FAIL("no error");
  } catch (const IoError& error) {
    REQUIRE(error.kind() == IoErrorKind::kOpenFailed);
    REQUIRE(error.path().find("absent.obj") != std::string::npos);
  }
  REQUIRE_THROWS_AS(facerig::ImportTemplateFolder(folder / "nope"), IoError);
  fs::remove(folder / "neutral.obj");
  REQUIRE_THROWS_AS(facerig::ImportTemplateFolder(folder), IoError);
}

TEST_CASE("GlobMatch and GuessHeadUnits", "[template_folder]") {
  REQUIRE(facerig::GlobMatch("*.obj", "jawOpen.obj"));
  REQUIRE_FALSE(facerig::GlobMatch("*.obj", "jawOpen.obj.bak"));
  REQUIRE(facerig::GlobMatch("mouth*_?.obj", "mouthSmile_L.obj"));
  REQUIRE_FALSE(facerig::GlobMatch("mouth*_?.obj", "mouthClose.obj"));
  REQUIRE(facerig::GlobMatch("*", ""));
  REQUIRE(facerig::GuessHeadUnits(0.45f) == facerig::Units::kMetres);
  REQUIRE(facerig::GuessHeadUnits(47.5f) == facerig::Units::kCentimetres);
  REQUIRE(facerig::GuessHeadUnits(475.0f) == facerig::Units::kMillimetres);
  REQUIRE(facerig::GuessHeadUnits(5.0f) == facerig::Units::kUnknown);
}

TEST_CASE("ICT-FaceKit template folder imports (shared data)", "[template_folder][shared-data]") {
  facerig::TemplateImportReport report;
  const facerig::Rig rig = facerig::ImportTemplateFolder(facerig::test::IctDir(), {}, &report);
  REQUIRE(rig.vertex_count() == 26719);
  REQUIRE(rig.shape_count() == 53);  // from vertex_indices.json: no identities, no PupilDilate
  REQUIRE(rig.FindShape("jawOpen"));
  REQUIRE(rig.FindShape("eyeBlink_L"));
  REQUIRE_FALSE(rig.FindShape("identity000"));
  REQUIRE_FALSE(rig.FindShape("PupilDilate_L"));
  REQUIRE(rig.units() == facerig::Units::kCentimetres);
  REQUIRE(report.units_guessed);
  REQUIRE(rig.FindPart("M_Face"));
  REQUIRE(rig.FindPart("M_Teeth"));
  REQUIRE(rig.FindPart("M_Face")->first_vertex == 0u);
  REQUIRE(rig.FindPart("M_Teeth")->first_vertex == 17039u);
  REQUIRE(rig.uvs().size() == rig.vertex_count());
  REQUIRE(report.kept_entries == rig.total_shape_entries());
  REQUIRE(report.largest_dropped <= report.drop_threshold);
  // Sparse: well under the dense 53 x 26719 entries.
  REQUIRE(rig.total_shape_entries() < rig.shape_count() * rig.vertex_count() / 2);

  // Every shape at weight 1 reproduces its OBJ within the drop threshold.
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const std::string name(rig.shape_name(s));
    const facerig::Mesh expression = facerig::ReadObj(facerig::test::IctDir() / (name + ".obj"));
    std::vector<glm::vec3> posed(rig.positions().begin(), rig.positions().end());
    const facerig::BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      posed[shape.vertex_indices[i]] += shape.position_deltas[i];
    }
    float worst = 0.0f;
    for (std::size_t v = 0; v < posed.size(); ++v) {
      worst = std::max(worst, glm::length(posed[v] - expression.positions[v]));
    }
    INFO(name);
    REQUIRE(worst <= report.drop_threshold * 1.01f);
  }
}
