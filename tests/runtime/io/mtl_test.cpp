// MTL material libraries: ParseMtl, the names the writer chooses, FormatMtl
// and WriteMtl. OBJ files that use them are in obj_test.cpp.
#include "facerig/runtime/io/mtl.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// The IoError ParseMtl throws for `text`; fails the test when there is none.
IoError ErrorOf(const std::string& text) {
  try {
    ParseMtl(text, "bad.mtl");
  } catch (const IoError& error) {
    return error;
  }
  FAIL("no error for:\n" << text);
  throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("MTL: colour, alpha, roughness and maps with options and spaces", "[mtl]") {
  const std::string text =
      "# Blender MTL\n"
      "newmtl skin\n"
      "Ns 98\n"
      "Ka 1 1 1\n"
      "Kd 0.8 0.6 0.5\n"
      "illum 2\n"
      "map_Kd -bm 1.0 -o 0.1 0.2 -clamp on textures\\skin colour.png  \r\n"
      "map_Bump -bm 0.5 skin_normal.png\n"
      "\n"
      "NEWMTL lens glass\n"
      "kd 0.25\n"
      "Tr 0.75\n"
      "d 0.5\n"
      "norm lens_n.jpg\n"
      "newmtl tear\n"
      "Tr 0.25\n"
      "bump -imfchan l tear.png\n";
  const std::vector<MtlMaterial> materials = ParseMtl(text, "mem.mtl");
  REQUIRE(materials.size() == 3);
  const MtlMaterial& skin = materials[0];
  CHECK(skin.material.name == "skin");
  CHECK(skin.material.base_colour == glm::vec4(0.8f, 0.6f, 0.5f, 1.0f));
  CHECK(skin.material.alpha_mode == AlphaMode::kOpaque);
  CHECK(skin.material.roughness == Approx(std::sqrt(2.0f / 100.0f)));
  CHECK(skin.material.base_colour_image == -1);
  CHECK(skin.base_colour_map.file == "textures/skin colour.png");
  CHECK(skin.base_colour_map.statement == "map_Kd");
  CHECK(skin.base_colour_map.line == 7);
  CHECK(skin.normal_map.file == "skin_normal.png");
  // A name with a space; Kd with one number is grey; d wins over Tr.
  const MtlMaterial& lens = materials[1];
  CHECK(lens.material.name == "lens glass");
  CHECK(lens.material.base_colour == glm::vec4(0.25f, 0.25f, 0.25f, 0.5f));
  CHECK(lens.material.alpha_mode == AlphaMode::kBlend);
  CHECK(lens.material.roughness == 1.0f);
  CHECK(lens.normal_map.file == "lens_n.jpg");
  CHECK(lens.normal_map.statement == "norm");
  CHECK(lens.base_colour_map.file.empty());
  // Tr alone: alpha 1 - Tr.
  CHECK(materials[2].material.base_colour.a == 0.75f);
  CHECK(materials[2].material.alpha_mode == AlphaMode::kBlend);
  CHECK(materials[2].normal_map.file == "tear.png");
}

TEST_CASE("MTL: values outside 0 to 1 are clamped, spectral colours keep the default", "[mtl]") {
  const std::vector<MtlMaterial> materials =
      ParseMtl("newmtl a\nKd 1.5 -0.5 0.5\nd 2\nNs -4\nnewmtl b\nKd spectral blue.rfl\n", "mem.mtl");
  REQUIRE(materials.size() == 2);
  CHECK(materials[0].material.base_colour == glm::vec4(1.0f, 0.0f, 0.5f, 1.0f));
  CHECK(materials[0].material.alpha_mode == AlphaMode::kOpaque);
  CHECK(materials[0].material.roughness == 1.0f);
  CHECK(materials[1].material.base_colour == glm::vec4(1.0f));
  CHECK(ParseMtl("# nothing\n\n", "mem.mtl").empty());
}

TEST_CASE("MTL: malformed statements give short errors with the line", "[mtl][malformed]") {
  struct Case {
    const char* text;
    IoErrorKind kind;
    std::int64_t line;
  };
  const Case cases[] = {
      {"Kd 1 1 1\n", IoErrorKind::kParse, 1},
      {"# c\nmap_Kd skin.png\n", IoErrorKind::kParse, 2},
      {"newmtl\n", IoErrorKind::kParse, 1},
      {"newmtl a\nKd\n", IoErrorKind::kParse, 2},
      {"newmtl a\nKd 1 1\n", IoErrorKind::kParse, 2},
      {"newmtl a\nKd 1 red 1\n", IoErrorKind::kParse, 2},
      {"newmtl a\nKd 1 nan 1\n", IoErrorKind::kNonFinite, 2},
      {"newmtl a\nd 1e999\n", IoErrorKind::kNonFinite, 2},
      {"newmtl a\nd\n", IoErrorKind::kParse, 2},
      {"newmtl a\nNs inf\n", IoErrorKind::kNonFinite, 2},
      {"newmtl a\n\nmap_Kd -bm 1.0\n", IoErrorKind::kParse, 3},
      {"newmtl a\nnorm   \n", IoErrorKind::kParse, 2},
  };
  for (const Case& c : cases) {
    const IoError error = ErrorOf(c.text);
    INFO(c.text << "-> " << error.what());
    CHECK(error.kind() == c.kind);
    CHECK(error.line() == c.line);
    CHECK(std::string(error.what()).find("bad.mtl") != std::string::npos);
    CHECK(error.message().size() < 80);
  }
  // A long bad number is quoted short.
  const IoError long_number = ErrorOf("newmtl a\nd " + std::string(5000, '7') + "x\n");
  CHECK(long_number.message().size() < 80);
}

TEST_CASE("MTL: mtllib names, several or one with spaces", "[mtl]") {
  CHECK(SplitMtllibNames(" a.mtl  sub\\b.MTL\r") == std::vector<std::string>{"a.mtl", "sub/b.MTL"});
  CHECK(SplitMtllibNames("my head.mtl") == std::vector<std::string>{"my head.mtl"});
  CHECK(SplitMtllibNames("head.mtl extra") == std::vector<std::string>{"head.mtl extra"});
  CHECK(SplitMtllibNames("   ").empty());
}

TEST_CASE("MTL: written names are safe and unique", "[mtl]") {
  const std::vector<Material> materials = {Material{.name = "skin"}, Material{.name = "skin"},
                                           Material{.name = "two words\t#x"}, Material{.name = ""}};
  CHECK(MtlMaterialNames(materials) == std::vector<std::string>{"skin", "skin_2", "two_words__x", "material3"});
  std::vector<EncodedImage> images(5);
  images[0].name = "Skin.png";
  images[1].name = "skin.PNG";
  images[2].name = "../../etc/passwd";
  images[3].name = ".hidden photo.jpeg";
  images[3].format = ImageFormat::kJpeg;
  images[4].name = "";
  CHECK(ImageFileNames(images) ==
        std::vector<std::string>{"Skin.png", "skin_2.png", "passwd.png", "hidden_photo.jpg", "image4.png"});
}

TEST_CASE("MTL: FormatMtl reads back as the same materials", "[mtl]") {
  const std::vector<Material> materials = {
      Material{.name = "skin", .base_colour = {0.8f, 0.6f, 0.5f, 1.0f}, .base_colour_image = 1, .normal_image = 0,
               .roughness = 0.4f},
      Material{.name = "lens", .base_colour = {0.1f, 0.2f, 0.3f, 0.25f}, .alpha_mode = AlphaMode::kBlend,
               .roughness = 0.05f},
      Material{.name = "teeth", .roughness = 1.0f}};
  const std::vector<std::string> names = MtlMaterialNames(materials);
  const std::vector<std::string> files = {"normal.png", "colour.jpg"};
  const std::vector<MtlMaterial> read = ParseMtl(FormatMtl(materials, names, files), "mem.mtl");
  REQUIRE(read.size() == materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) {
    INFO(materials[m].name);
    CHECK(read[m].material.name == materials[m].name);
    CHECK(read[m].material.base_colour == materials[m].base_colour);
    CHECK(read[m].material.alpha_mode == materials[m].alpha_mode);
    CHECK(read[m].material.roughness == Approx(materials[m].roughness).epsilon(1e-5));
  }
  CHECK(read[0].base_colour_map.file == "colour.jpg");
  CHECK(read[0].normal_map.file == "normal.png");
  CHECK(read[1].base_colour_map.file.empty());
}

TEST_CASE("MTL: WriteMtl writes the library and the image bytes, and refuses bad names", "[mtl]") {
  const fs::path folder = test::OutputPath("mtl_write");
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::vector<EncodedImage> images = {test::CheckerImage("skin.png", 8, 2, {200, 150, 120, 255}, {90, 40, 30, 255}),
                                            test::CheckerImage("skin.png", 4, 1, {128, 128, 255, 255}, {0, 0, 0, 255})};
  const std::vector<Material> materials = {Material{.name = "skin", .base_colour_image = 0, .normal_image = 1}};
  const MtlReference reference = WriteMtl(folder, "face.mtl", materials, images);
  CHECK(reference.mtl_file == "face.mtl");
  CHECK(reference.material_names == std::vector<std::string>{"skin"});
  const std::vector<std::byte> first = ReadInputFile(folder / "skin.png");
  const std::vector<std::byte> second = ReadInputFile(folder / "skin_2.png");
  CHECK(std::equal(first.begin(), first.end(), reinterpret_cast<const std::byte*>(images[0].bytes.data())));
  CHECK(second.size() == images[1].bytes.size());
  const std::vector<MtlMaterial> read = ParseMtl(ReadInputText(folder / "face.mtl"), "face.mtl");
  REQUIRE(read.size() == 1);
  CHECK(read[0].normal_map.file == "skin_2.png");

  for (const char* bad : {"../face.mtl", "sub/face.mtl", "", ".."}) {
    INFO(bad);
    try {
      WriteMtl(folder, bad, materials, images);
      FAIL("no error");
    } catch (const IoError& error) {
      CHECK(error.kind() == IoErrorKind::kWriteFailed);
    }
  }
  const std::vector<Material> dangling = {Material{.name = "skin", .base_colour_image = 2}};
  try {
    WriteMtl(folder, "face.mtl", dangling, images);
    FAIL("no error");
  } catch (const IoError& error) {
    CHECK(error.kind() == IoErrorKind::kInvalidRig);
  }
}

}  // namespace facerig
