// OBJ files with MTL libraries and images: ReadObj following mtllib and
// map_* statements (and refusing hostile ones), WriteObj writing them.
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/image_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/rig_builder.h"
#include "support/hostile_files.h"
#include "support/jpeg_header.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

constexpr const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

// An empty folder under the test output folder.
fs::path FreshFolder(const std::string& name) {
  const fs::path folder = test::OutputPath("obj_materials") / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

void WriteBytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  WriteFileAtomically(path, std::as_bytes(std::span(bytes.data(), bytes.size())));
}

void WriteText(const fs::path& path, const std::string& text) { WriteFileAtomically(path, std::string_view(text)); }

// A quad OBJ in `folder` using materials "skin" and "lens" (and `extra`
// statements before the faces).
fs::path WriteQuadObj(const fs::path& folder, const std::string& extra) {
  const fs::path obj = folder / "face.obj";
  WriteText(obj, std::string(kQuad) + extra + "usemtl skin\nf 1/1 2/2 3/3\nusemtl lens\nf 1/1 3/3 4/4\n");
  return obj;
}

// what() of the IoError ReadObj throws; fails the test when there is none.
std::string ReadObjError(const fs::path& obj) {
  try {
    ReadObj(obj);
  } catch (const IoError& error) {
    return error.what();
  }
  FAIL("no error reading " << obj);
  return {};
}

const Material* FindMaterial(const Mesh& mesh, const std::string& name) {
  for (const Material& material : mesh.materials) {
    if (material.name == name) return &material;
  }
  return nullptr;
}

// The grid rig with materials "skin" (left part: colour and normal images)
// and "lens" (right part: translucent, no image).
Rig GridRigWithMaterials() {
  RawRig raw = test::MakeGridRawRig(5, 0);
  raw.materials = {Material{.name = "skin",
                            .base_colour = {0.8f, 0.6f, 0.5f, 1.0f},
                            .base_colour_image = 0,
                            .normal_image = 1,
                            .roughness = 0.5f},
                   Material{.name = "lens glass",
                            .base_colour = {0.2f, 0.3f, 0.4f, 0.35f},
                            .alpha_mode = AlphaMode::kBlend,
                            .roughness = 0.1f}};
  raw.images = {test::CheckerImage("skin.png", 8, 2, {200, 150, 120, 255}, {90, 40, 30, 255}),
                test::CheckerImage("skin.png", 4, 1, {128, 128, 255, 255}, {120, 120, 250, 255})};
  REQUIRE(raw.parts.size() == 2);
  raw.parts[0].material = 0;
  raw.parts[1].material = 1;
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  INFO(problem);
  REQUIRE(rig);
  return std::move(*rig);
}

// The read mesh's materials against the rig's: names, colours, alpha, roughness, image bytes.
void CheckSameMaterials(const Mesh& read, const Rig& rig) {
  REQUIRE(read.materials.size() == rig.materials().size());
  for (const Material& written : rig.materials()) {
    INFO(written.name);
    const Material* back = FindMaterial(read, written.name == "lens glass" ? "lens_glass" : written.name);
    REQUIRE(back != nullptr);
    CHECK(back->base_colour == written.base_colour);
    CHECK(back->alpha_mode == written.alpha_mode);
    CHECK(back->roughness == Approx(written.roughness).epsilon(1e-5));
    for (const auto image : {&Material::base_colour_image, &Material::normal_image}) {
      REQUIRE((back->*image < 0) == (written.*image < 0));
      if (written.*image >= 0) {
        CHECK(read.images[static_cast<std::size_t>(back->*image)].bytes ==
              rig.images()[static_cast<std::size_t>(written.*image)].bytes);
      }
    }
  }
}

}  // namespace

TEST_CASE("OBJ materials: mtllib, colours, alpha and image bytes are read", "[obj][mtl]") {
  const fs::path folder = FreshFolder("read");
  fs::create_directories(folder / "textures");
  const std::vector<std::uint8_t> skin_png = test::CheckerPng(8, 2, {200, 150, 120, 255}, {90, 40, 30, 255});
  const std::vector<std::uint8_t> normal_jpg = test::JpegHeader(16, 8);
  WriteBytes(folder / "textures" / "skin colour.png", skin_png);
  WriteBytes(folder / "normal.jpg", normal_jpg);
  WriteText(folder / "face.mtl",
            "newmtl skin\nKd 0.8 0.6 0.5\nNs 48\nmap_Kd -bm 1 textures\\skin colour.png\nmap_Bump normal.jpg\n");
  WriteText(folder / "lens.mtl",
            "newmtl lens\nKd 0.2 0.3 0.4\nd 0.5\nnorm normal.jpg\nnewmtl skin\nKd 0 0 0\n");
  ObjStats stats;
  const Mesh mesh = ReadObj(WriteQuadObj(folder, "mtllib face.mtl lens.mtl\n"), &stats);
  CHECK(stats.mtl_files == std::vector<std::string>{"face.mtl", "lens.mtl"});
  CHECK(stats.warnings.empty());
  REQUIRE(mesh.Validate());
  REQUIRE(mesh.materials.size() == 2);
  const Material& skin = mesh.materials[0];
  CHECK(skin.name == "skin");
  CHECK(skin.base_colour == glm::vec4(0.8f, 0.6f, 0.5f, 1.0f));  // the first definition wins
  CHECK(skin.roughness == Approx(0.2f));
  const Material& lens = mesh.materials[1];
  CHECK(lens.base_colour.a == 0.5f);
  CHECK(lens.alpha_mode == AlphaMode::kBlend);
  CHECK(lens.base_colour_image == -1);
  // normal.jpg is named twice and read once.
  REQUIRE(mesh.images.size() == 2);
  CHECK(lens.normal_image == skin.normal_image);
  const EncodedImage& colour = mesh.images[static_cast<std::size_t>(skin.base_colour_image)];
  CHECK(colour.name == "skin colour.png");
  CHECK(colour.bytes == skin_png);
  CHECK(colour.width == 8);
  const EncodedImage& normal = mesh.images[static_cast<std::size_t>(skin.normal_image)];
  CHECK(normal.format == ImageFormat::kJpeg);
  CHECK(normal.bytes == normal_jpg);
  // The rig keeps them.
  const RawRig raw = ToRawRig(mesh);
  CHECK(raw.materials.size() == 2);
  CHECK(raw.images.size() == 2);
}

TEST_CASE("OBJ materials: missing MTL and image files are warnings, not errors", "[obj][mtl]") {
  const fs::path folder = FreshFolder("missing");
  WriteText(folder / "face.mtl", "newmtl skin\nKd 0.8 0.6 0.5\nmap_Kd skin.png\n");
  ObjStats stats;
  const Mesh mesh = ReadObj(WriteQuadObj(folder, "mtllib face.mtl gone.mtl\n"), &stats);
  REQUIRE(stats.warnings.size() == 3);
  CHECK(stats.warnings[0].find("gone.mtl") != std::string::npos);
  CHECK(stats.warnings[1].find("skin.png") != std::string::npos);
  CHECK(stats.warnings[2].find("lens") != std::string::npos);
  REQUIRE(mesh.materials.size() == 2);
  CHECK(mesh.materials[0].base_colour == glm::vec4(0.8f, 0.6f, 0.5f, 1.0f));
  CHECK(mesh.materials[0].base_colour_image == -1);
  CHECK(mesh.materials[1].base_colour == glm::vec4(1.0f));
  CHECK(mesh.images.empty());
  // ParseObj opens nothing: names only.
  ObjStats parsed;
  const Mesh by_name = ParseObj(ReadInputText(folder / "face.obj"), "face.obj", &parsed);
  CHECK(by_name.materials[0].base_colour == glm::vec4(1.0f));
  CHECK(parsed.mtl_files.size() == 2);
  CHECK(parsed.warnings.empty());
}

TEST_CASE("OBJ materials: hostile mtllib and map names are short errors naming the file", "[obj][mtl][malformed]") {
  const fs::path folder = FreshFolder("hostile");
  const fs::path outside = FreshFolder("hostile_outside");
  WriteText(outside / "x.mtl", "newmtl skin\n");
  WriteBytes(outside / "skin.png", test::CheckerPng(4, 1, {0, 0, 0, 255}, {0, 0, 0, 255}));
  fs::create_symlink(outside, folder / "link");
  struct Case {
    const char* obj_extra;
    const char* mtl_text;
    const char* named;  // what the error must quote
  };
  const Case cases[] = {
      {"mtllib ../hostile_outside/x.mtl\n", nullptr, "../hostile_outside/x.mtl"},
      {"mtllib /etc/passwd\n", nullptr, "/etc/passwd"},
      {"mtllib link/x.mtl\n", nullptr, "link/x.mtl"},
      {"mtllib face.mtl\n", "newmtl skin\nmap_Kd ../hostile_outside/skin.png\n", "../hostile_outside/skin.png"},
      {"mtllib face.mtl\n", "newmtl skin\nmap_Kd /etc/passwd\n", "/etc/passwd"},
      {"mtllib face.mtl\n", "newmtl skin\nnorm link/skin.png\n", "link/skin.png"},
      {"mtllib face.mtl\n", "newmtl skin\nmap_Kd face.mtl\n", "face.mtl"},  // not an image
      {"mtllib face.mtl\n", "newmtl skin\nKd 1 nan 1\n", "face.mtl"},
  };
  for (const Case& c : cases) {
    INFO(c.obj_extra << (c.mtl_text ? c.mtl_text : ""));
    if (c.mtl_text) WriteText(folder / "face.mtl", c.mtl_text);
    const std::string error = ReadObjError(WriteQuadObj(folder, c.obj_extra));
    CHECK(error.find(c.named) != std::string::npos);
    CHECK(error.size() < 300);
  }
}

TEST_CASE("OBJ materials: FIFOs, oversized and broken images fail without hanging", "[obj][mtl][malformed]") {
  const fs::path folder = FreshFolder("fifo");
  test::MakeFifo(folder / "pipe.mtl");
  const fs::path obj_with_fifo_mtl = WriteQuadObj(folder, "mtllib pipe.mtl\n");
  std::string error = test::ErrorWithoutHanging(folder / "pipe.mtl", [&] { ReadObj(obj_with_fifo_mtl); });
  CHECK(error.find("pipe.mtl") != std::string::npos);
  CHECK(error.find("FIFO") != std::string::npos);

  test::MakeFifo(folder / "pipe.png");
  WriteText(folder / "face.mtl", "newmtl skin\nKd 1 1 1\n\nmap_Kd pipe.png\n");
  const fs::path obj = WriteQuadObj(folder, "mtllib face.mtl\n");
  error = test::ErrorWithoutHanging(folder / "pipe.png", [&] { ReadObj(obj); });
  CHECK(error.find("face.mtl:4") != std::string::npos);
  CHECK(error.find("pipe.png") != std::string::npos);
  CHECK(error.find("FIFO") != std::string::npos);

  // A PNG claiming 23170 x 23170 RGBA pixels (2 GB), and a JPEG cut before its frame header.
  std::vector<std::uint8_t> huge = test::CheckerPng(4, 1, {0, 0, 0, 255}, {0, 0, 0, 255});
  for (const std::size_t at : {16u, 20u}) {
    huge[at] = huge[at + 1] = 0x00;
    huge[at + 2] = 0x5A;
    huge[at + 3] = 0x82;
  }
  WriteBytes(folder / "huge.png", huge);
  std::vector<std::uint8_t> cut = test::JpegHeader(64, 64);
  cut.resize(22);
  WriteBytes(folder / "cut.jpg", cut);
  for (const char* name : {"huge.png", "cut.jpg"}) {
    WriteText(folder / "face.mtl", std::string("newmtl skin\nmap_Kd ") + name + "\n");
    error = ReadObjError(obj);
    INFO(error);
    CHECK(error.find(name) != std::string::npos);
    CHECK(error.find("face.mtl:2") != std::string::npos);
  }
  // An MTL and an image over their byte caps (sparse files).
  WriteBytes(folder / "big.png", huge);
  fs::resize_file(folder / "big.png", kMaxImageFileBytes + 1);
  WriteText(folder / "face.mtl", "newmtl skin\nmap_Kd big.png\n");
  CHECK(ReadObjError(obj).find("big.png") != std::string::npos);
  fs::remove(folder / "big.png");
  WriteText(folder / "big.mtl", "newmtl skin\n");
  fs::resize_file(folder / "big.mtl", kMaxMtlFileBytes + 1);
  CHECK(ReadObjError(WriteQuadObj(folder, "mtllib big.mtl\n")).find("big.mtl") != std::string::npos);
}

TEST_CASE("OBJ materials: a rig written with materials reads back with them", "[obj][mtl]") {
  const Rig rig = GridRigWithMaterials();
  const fs::path folder = FreshFolder("write");
  WriteObj(folder / "head.obj", rig);
  CHECK(fs::exists(folder / "head.mtl"));
  CHECK(fs::exists(folder / "skin.png"));
  CHECK(fs::exists(folder / "skin_2.png"));  // the two images share a name
  ObjStats stats;
  const Mesh read = ReadObj(folder / "head.obj", &stats);
  CHECK(stats.warnings.empty());
  REQUIRE(read.Validate());
  CheckSameMaterials(read, rig);
  // Each part keeps its material.
  const RawRig raw = ToRawRig(read);
  REQUIRE(raw.parts.size() == 2);
  CHECK(raw.materials[static_cast<std::size_t>(raw.parts[0].material)].name == "skin");
  CHECK(raw.parts[0].triangle_count == rig.parts()[0].triangle_count);

  // Without materials, no MTL.
  const fs::path plain = FreshFolder("write_plain");
  WriteObj(plain / "head.obj", test::MakeGridRig(3, 0));
  CHECK(ReadInputText(plain / "head.obj").find("mtllib") == std::string::npos);
  CHECK_FALSE(fs::exists(plain / "head.mtl"));
}

TEST_CASE("OBJ materials: a folder of OBJs shares one MTL and one set of images", "[obj][mtl]") {
  const Rig rig = GridRigWithMaterials();
  const fs::path folder = FreshFolder("shared");
  const MtlReference mtl = WriteMtl(folder, "materials.mtl", rig.materials(), rig.images());
  WriteObj(folder / "neutral.obj", rig, mtl);
  std::vector<glm::vec3> moved(rig.positions().begin(), rig.positions().end());
  for (glm::vec3& p : moved) p.z += 0.25f;
  WriteObj(folder / "jawOpen.obj", moved, rig.normals(), rig.uvs(), rig.triangles(), rig.parts(), mtl);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++files;
  CHECK(files == 5);  // two OBJs, one MTL, two images
  for (const char* name : {"neutral.obj", "jawOpen.obj"}) {
    INFO(name);
    CHECK(ReadInputText(folder / name).find("mtllib materials.mtl\n") != std::string::npos);
    ObjStats stats;
    const Mesh read = ReadObj(folder / name, &stats);
    CHECK(stats.warnings.empty());
    CheckSameMaterials(read, rig);
  }
  // A part without a material reads back as the default one, with no warning.
  std::vector<Part> parts(rig.parts().begin(), rig.parts().end());
  parts[1].material = -1;
  WriteObj(folder / "partial.obj", rig.positions(), rig.normals(), rig.uvs(), rig.triangles(), parts, mtl);
  ObjStats stats;
  const Mesh partial = ReadObj(folder / "partial.obj", &stats);
  CHECK(stats.warnings.empty());
  REQUIRE(partial.materials.size() == 2);
  CHECK(partial.materials[1].name == "default");
  CHECK(partial.materials[1].base_colour == glm::vec4(1.0f));
  // No library (a rig without materials): as the writer without one.
  WriteObj(folder / "plain.obj", rig.positions(), rig.normals(), rig.uvs(), rig.triangles(), rig.parts(), MtlReference{});
  CHECK(ReadInputText(folder / "plain.obj").find("mtllib") == std::string::npos);
  CHECK(ReadObj(folder / "plain.obj").materials[0].name == "left");
}

}  // namespace facerig
