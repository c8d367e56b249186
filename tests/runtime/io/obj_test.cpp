#include "facerig/runtime/io/obj.h"

#include <fstream>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "support/test_meshes.h"

using facerig::IoError;
using facerig::IoErrorKind;
using facerig::ParseObj;

namespace {
IoErrorKind KindOf(const std::string& text, std::int64_t expected_line = -1) {
  try {
    ParseObj(text, "bad.obj");
  } catch (const IoError& error) {
    REQUIRE(std::string(error.what()).find("bad.obj") != std::string::npos);
    if (expected_line >= 0) REQUIRE(error.line() == expected_line);
    return error.kind();
  }
  FAIL("no error for:\n" << text);
  return IoErrorKind::kParse;
}
}  // namespace

TEST_CASE("OBJ: quads, n-gons, all index forms, negative indices", "[obj]") {
  const std::string text =
      "# comment\nmtllib x.mtl\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "vn 0 0 1\n"
      "g first\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1\n"   // quad, v/vt/vn
      "s off\n"
      "f 2//1 5//1 3//1\n"            // v//vn
      "g second\n"
      "f -4/-3 -1/-2 -3/-1\n"          // negative, v/vt: vertices 2 5 3
      "f 1 2 5 3 4\n";                 // pentagon, plain
  facerig::ObjStats stats;
  const facerig::Mesh parsed = ParseObj(text, "mem.obj", &stats);
  REQUIRE(parsed.Validate());
  REQUIRE(parsed.corner_uvs.size() == parsed.triangles.size() * 3);
  REQUIRE(parsed.corner_uvs[3 * 3 + 1] == glm::vec2(1, 1));  // the negative face: vt -2 is the file's third
  REQUIRE(parsed.materials.empty());
  const facerig::RawRig mesh = facerig::ToRawRig(parsed);
  REQUIRE(mesh.positions.size() == 5);
  REQUIRE(stats.polygon_count == 4);
  REQUIRE(mesh.triangles.size() == 2 + 1 + 1 + 3);
  REQUIRE(mesh.triangles[0] == facerig::Triangle{0, 1, 2});
  REQUIRE(mesh.triangles[1] == facerig::Triangle{0, 2, 3});
  REQUIRE(mesh.triangles[3] == facerig::Triangle{1, 4, 2});
  REQUIRE(mesh.parts.size() == 2);
  REQUIRE(mesh.parts[0].name == "first");
  REQUIRE(mesh.parts[0].triangle_count == 3);
  REQUIRE(mesh.parts[1].name == "second");
  REQUIRE(mesh.parts[1].first_triangle == 3);
  REQUIRE(mesh.uvs.size() == 5);
  REQUIRE(mesh.uvs[2] == glm::vec2(1, 1));
  REQUIRE(mesh.normals.size() == 5);
  // Vertex 3 gets vt 3 from the quad, then vt 4 (-1) from the negative face:
  // one seam; vertex 2 gets vt 2 both times: none.
  REQUIRE(facerig::PerVertexAttributes(parsed).uv_seam_vertices == 1);
}

TEST_CASE("OBJ: materials become parts, reordered so each part is one range", "[obj]") {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "usemtl skin\nf 1 2 3\n"
      "usemtl teeth\nf 1 3 4\n"
      "usemtl skin\nf 2 3 4\n";
  const facerig::Mesh parsed = ParseObj(text, "mem.obj");
  REQUIRE(parsed.materials.size() == 2);
  REQUIRE(parsed.materials[1].name == "teeth");
  REQUIRE(parsed.triangle_materials == std::vector<std::uint32_t>{0, 1, 0});
  REQUIRE(parsed.triangles[1] == facerig::Triangle{0, 2, 3});  // the file's order
  const facerig::RawRig mesh = facerig::ToRawRig(parsed);
  REQUIRE(mesh.parts.size() == 2);
  REQUIRE(mesh.parts[0].name == "skin");
  REQUIRE(mesh.parts[0].triangle_count == 2);
  REQUIRE(mesh.triangles[1] == facerig::Triangle{1, 2, 3});
  REQUIRE(mesh.parts[1].name == "teeth");
  REQUIRE(mesh.triangles[2] == facerig::Triangle{0, 2, 3});
}

TEST_CASE("OBJ: usemtl names may contain spaces, and ParseObj records mtllib names and opens nothing", "[obj]") {
  const std::string text =
      "mtllib face.mtl eyes.MTL\nmtllib my head.mtl\r\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\n"
      "usemtl lens glass \r\nf 1 2 3\n";
  facerig::ObjStats stats;
  const facerig::Mesh parsed = ParseObj(text, "/nonexistent/mem.obj", &stats);
  REQUIRE(parsed.materials.size() == 1);
  REQUIRE(parsed.materials[0].name == "lens glass");
  REQUIRE(parsed.materials[0].base_colour == glm::vec4(1.0f));
  REQUIRE(stats.mtl_files == std::vector<std::string>{"face.mtl", "eyes.MTL", "my head.mtl"});
  REQUIRE(stats.warnings.empty());
}

TEST_CASE("OBJ: malformed input gives typed errors with the line", "[obj][malformed]") {
  REQUIRE(KindOf("") == IoErrorKind::kEmpty);
  REQUIRE(KindOf("# only a comment\n") == IoErrorKind::kEmpty);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\n") == IoErrorKind::kEmpty);  // no faces
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4) == IoErrorKind::kIndexOutOfRange);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4) == IoErrorKind::kIndexOutOfRange);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", 4) == IoErrorKind::kParse);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4) == IoErrorKind::kParse);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/7\n", 4) == IoErrorKind::kIndexOutOfRange);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3//9\n", 4) == IoErrorKind::kIndexOutOfRange);
  REQUIRE(KindOf("v 0 0\n", 1) == IoErrorKind::kParse);
  REQUIRE(KindOf("v 0 zero 0\n", 1) == IoErrorKind::kParse);
  REQUIRE(KindOf("v 0 0 0\nv nan 0 0\n", 2) == IoErrorKind::kNonFinite);
  REQUIRE(KindOf("v 0 0 0\nv inf 0 0\n", 2) == IoErrorKind::kNonFinite);
  REQUIRE(KindOf("v 0 0 1e999\n", 1) == IoErrorKind::kNonFinite);
  REQUIRE(KindOf("v 0 0 0\nvt 0.5 nan\n", 2) == IoErrorKind::kNonFinite);
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", 4) == IoErrorKind::kParse);
  // A file cut off in the middle of a face line.
  REQUIRE(KindOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2", 5) == IoErrorKind::kParse);
}

TEST_CASE("OBJ: a missing file names the path", "[obj][malformed]") {
  try {
    facerig::ReadObj(facerig::test::OutputPath("does_not_exist.obj"));
    FAIL("no error");
  } catch (const IoError& error) {
    REQUIRE(error.kind() == IoErrorKind::kOpenFailed);
    REQUIRE(std::string(error.what()).find("does_not_exist.obj") != std::string::npos);
  }
}

TEST_CASE("OBJ: write then read gives the same mesh", "[obj]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(5, 0);
  const auto path = facerig::test::OutputPath("grid_roundtrip.obj");
  facerig::WriteObj(path, rig);
  const facerig::Mesh read = facerig::ReadObj(path);
  const facerig::RawRig mesh = facerig::ToRawRig(read);
  REQUIRE(mesh.positions.size() == rig.vertex_count());
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
    REQUIRE(mesh.positions[v] == rig.positions()[v]);  // shortest round-trip float text
    REQUIRE(mesh.uvs[v] == rig.uvs()[v]);
    REQUIRE(mesh.normals[v] == rig.normals()[v]);
  }
  REQUIRE(std::equal(mesh.triangles.begin(), mesh.triangles.end(), rig.triangles().begin()));
  REQUIRE(mesh.parts.size() == 2);
  REQUIRE(mesh.parts[1].name == "right");
  REQUIRE(facerig::PerVertexAttributes(read).uv_seam_vertices == 0);
}

TEST_CASE("OBJ: writing into a missing folder fails cleanly and leaves the old file", "[obj]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(3, 0);
  try {
    facerig::WriteObj(facerig::test::OutputPath("no/such/dir/x.obj"), rig);
    FAIL("no error");
  } catch (const IoError& error) {
    REQUIRE(error.kind() == IoErrorKind::kWriteFailed);
  }
  const auto path = facerig::test::OutputPath("keep.obj");
  facerig::WriteFileAtomically(path, std::string_view("old"));
  facerig::WriteObj(path, rig);
  REQUIRE(facerig::ReadObj(path).positions.size() == 9);
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
    REQUIRE(entry.path().filename().string().find(".tmp-") == std::string::npos);
  }
}
