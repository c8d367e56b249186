// The default head's UVs, painted textures and materials, as its GLB carries them.
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/runtime/io/gltf.h"
#include "support/default_head_poses.h"
#include "support/gltf_validator.h"

namespace {

std::vector<char> ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A freshly generated head written as GLB into the test output folder.
// The file's stem names the glTF mesh, so `folder` tells runs apart.
std::filesystem::path WriteHeadGlb(const facerig::Rig& rig, const char* folder) {
  const std::filesystem::path directory = std::filesystem::path(FACERIG_TEST_OUTPUT_DIR) / "default_head_texture" / folder;
  std::filesystem::create_directories(directory);
  const std::filesystem::path path = directory / "default_head.glb";
  facerig::WriteGltf(path, rig);
  return path;
}

// The texel (nearest) under a UV, as 0..255 RGB.
glm::vec3 Texel(const facerig::RgbImage& image, glm::vec2 uv) {
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(image.width)), 0, image.width - 1);
  // The rig's v goes up (OBJ's convention); image rows go down.
  const int y = std::clamp(static_cast<int>((1.0f - uv.y) * static_cast<float>(image.height)), 0, image.height - 1);
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) * 3;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

// Red over green: lips and flushed skin are redder than plain skin whatever their brightness.
float Redness(const glm::vec3& rgb) { return rgb.r / std::max(rgb.g, 1.0f); }

const facerig::Material& PartMaterial(const facerig::Rig& rig, const char* part) {
  const facerig::Part* p = rig.FindPart(part);
  REQUIRE(p);
  REQUIRE(p->material >= 0);
  REQUIRE(static_cast<std::size_t>(p->material) < rig.materials().size());
  return rig.materials()[static_cast<std::size_t>(p->material)];
}

}  // namespace

TEST_CASE("Default head: the GLB carries UVs, materials and the painted textures", "[default_head][texture]") {
  const facerig::Rig& head = facerig::test::DefaultHead();
  const std::filesystem::path path = WriteHeadGlb(head, "materials");
  facerig::test::RequireValidatorAccepts(path);
  const facerig::Rig glb = facerig::ReadGltf(path);
  REQUIRE(glb.uvs().size() == glb.vertex_count());
  REQUIRE(glb.images().size() == 4);
  for (const facerig::EncodedImage& image : glb.images()) {
    CHECK(image.format == facerig::ImageFormat::kPng);
    CHECK(image.width == image.height);
  }
  const facerig::Material& skin = PartMaterial(glb, "skin");
  REQUIRE(skin.base_colour_image >= 0);
  CHECK(glb.images()[static_cast<std::size_t>(skin.base_colour_image)].width == 1024);
  CHECK(skin.roughness == Approx(0.6f));
  for (const char* eye_part : {"eye_white_L", "iris_R", "pupil_L"}) {
    const facerig::Material& eye = PartMaterial(glb, eye_part);
    CHECK(eye.base_colour_image >= 0);
    CHECK(eye.base_colour_image != skin.base_colour_image);
    CHECK(eye.roughness < 0.3f);
  }
  const facerig::Material& teeth = PartMaterial(glb, "teeth_upper");
  CHECK(teeth.base_colour_image >= 0);
  CHECK(teeth.base_colour_image != skin.base_colour_image);
  CHECK(&PartMaterial(glb, "teeth_lower") == &teeth);
  // The mouth interior: red at the lips, dark deep inside, so the teeth do not glow against it.
  const facerig::Material& mouth = PartMaterial(glb, "mouth_inner");
  REQUIRE(mouth.base_colour_image >= 0);
  const facerig::RgbImage inside = facerig::DecodeImage(glb.images()[static_cast<std::size_t>(mouth.base_colour_image)]);
  const facerig::Part* inner = glb.FindPart("mouth_inner");
  glm::vec3 at_lips(0.0f), deepest(255.0f);
  for (std::uint32_t v = inner->first_vertex; v < inner->first_vertex + inner->vertex_count; ++v) {
    const glm::vec3 c = Texel(inside, glb.uvs()[v]);
    if (c.r > at_lips.r) at_lips = c;
    if (c.r < deepest.r) deepest = c;
  }
  CHECK(Redness(at_lips) > 1.6f);
  CHECK(deepest.r < 40.0f);
  // UVs inside the texture everywhere.
  for (const glm::vec2& uv : glb.uvs()) {
    REQUIRE(uv.x >= 0.0f);
    REQUIRE(uv.x <= 1.0f);
    REQUIRE(uv.y >= 0.0f);
    REQUIRE(uv.y <= 1.0f);
  }
}

TEST_CASE("Default head: the painted skin has red lips, skin tones, and an iris with a pupil",
          "[default_head][texture]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& head = facerig::test::DefaultHead(&features);
  const facerig::Rig glb = facerig::ReadGltf(WriteHeadGlb(head, "pixels"));
  const facerig::Material& skin = PartMaterial(glb, "skin");
  const facerig::RgbImage albedo = facerig::DecodeImage(glb.images()[static_cast<std::size_t>(skin.base_colour_image)]);
  const auto uvs = glb.uvs();
  // Half way between the midline margin and the vermilion border: on the lip.
  const std::size_t mid = features.upper_lip.size() / 2;
  const glm::vec3 upper_lip = Texel(albedo, 0.5f * (uvs[features.upper_lip[mid]] + uvs[features.upper_lip_border]));
  const glm::vec3 lower_lip = Texel(albedo, 0.5f * (uvs[features.lower_lip[mid]] + uvs[features.lower_lip_border]));
  for (const std::uint32_t cheek : features.cheeks) {
    const glm::vec3 c = Texel(albedo, uvs[cheek]);
    INFO("cheek " << c.r << " " << c.g << " " << c.b << ", lips " << upper_lip.r << " " << upper_lip.g << " "
                  << upper_lip.b << " / " << lower_lip.r << " " << lower_lip.g << " " << lower_lip.b);
    CHECK(Redness(upper_lip) > 1.15f * Redness(c));
    CHECK(Redness(lower_lip) > 1.15f * Redness(c));
    CHECK(upper_lip.g < c.g - 30.0f);  // lips darker too, not just pinker
  }
  // Skin tones on the face away from the painted features: warm (R > G > B),
  // light to medium, not saturated.
  for (const std::uint32_t v : {features.cheeks[0], features.cheeks[1], features.nose_tip}) {
    const glm::vec3 c = Texel(albedo, uvs[v]);
    INFO("vertex " << v << ": " << c.r << " " << c.g << " " << c.b);
    CHECK(c.r > c.g);
    CHECK(c.g > c.b);
    CHECK(c.r > 150.0f);
    CHECK(c.r < 250.0f);
    CHECK(c.r - c.b > 30.0f);
    CHECK(c.r - c.b < 130.0f);
  }
  // The eye texture: the pupil (front pole) black, the sclera beside the iris white.
  const facerig::Material& eye = PartMaterial(glb, "pupil_L");
  const facerig::RgbImage eye_albedo = facerig::DecodeImage(glb.images()[static_cast<std::size_t>(eye.base_colour_image)]);
  const facerig::Part* pupil = glb.FindPart("pupil_L");
  const facerig::Part* white = glb.FindPart("eye_white_L");
  const glm::vec3 pupil_colour = Texel(eye_albedo, uvs[pupil->first_vertex]);
  const glm::vec3 white_colour = Texel(eye_albedo, uvs[white->first_vertex + 24]);  // the second ring
  CHECK(pupil_colour.r + pupil_colour.g + pupil_colour.b < 60.0f);
  CHECK(white_colour.r + white_colour.g + white_colour.b > 600.0f);
}

TEST_CASE("Default head: the painted teeth are ivory crowns with dark gaps, a gum line, the back in shadow",
          "[default_head][texture]") {
  const facerig::Rig glb = facerig::ReadGltf(WriteHeadGlb(facerig::test::DefaultHead(), "teeth"));
  const facerig::Material& material = PartMaterial(glb, "teeth_upper");
  const facerig::RgbImage teeth = facerig::DecodeImage(glb.images()[static_cast<std::size_t>(material.base_colour_image)]);
  const facerig::Part* upper = glb.FindPart("teeth_upper");
  // The row's band runs from its gum (highest v) to its biting edge (lowest v).
  float gum = 0.0f, edge = 1.0f;
  for (std::uint32_t v = upper->first_vertex; v < upper->first_vertex + upper->vertex_count; ++v) {
    gum = std::max(gum, glb.uvs()[v].y);
    edge = std::min(edge, glb.uvs()[v].y);
  }
  REQUIRE(gum > edge);
  // Across the front teeth at crown height: ivory crowns separated by dark gaps.
  const float crown = gum + 0.65f * (edge - gum);
  glm::vec3 brightest(0.0f);
  float darkest = 1e9f;
  int gaps = 0;
  bool in_gap = false;
  for (float u = 0.3f; u <= 0.7f; u += 0.001f) {
    const glm::vec3 c = Texel(teeth, {u, crown});
    if (c.r > brightest.r) brightest = c;
    darkest = std::min(darkest, c.r);
    const bool dark = c.r < 0.5f * 200.0f;
    if (dark && !in_gap) ++gaps;
    in_gap = dark;
  }
  INFO("brightest " << brightest.r << " " << brightest.g << " " << brightest.b << ", darkest red " << darkest);
  CHECK(gaps >= 5);  // between the incisors and canines
  CHECK(brightest.r > 200.0f);
  CHECK(brightest.r < 250.0f);                  // not paper white
  CHECK(brightest.r - brightest.b > 25.0f);     // ivory
  CHECK(darkest < 0.5f * brightest.r);
  // Above the crowns, the gum: pink.
  const glm::vec3 gum_colour = Texel(teeth, {0.5f, gum + 0.08f * (edge - gum)});
  CHECK(gum_colour.r > gum_colour.g + 50.0f);
  // The back teeth sit in the mouth's shadow.
  float back = 0.0f;
  for (float u = 0.02f; u <= 0.12f; u += 0.001f) back = std::max(back, Texel(teeth, {u, crown}).r);
  CHECK(back < 0.6f * brightest.r);
}

TEST_CASE("Default head: the textured GLB is the same bytes on every generation", "[default_head][texture]") {
  // The tests' shared head (built earlier in this process) against a new one.
  const std::vector<char> first = ReadBytes(WriteHeadGlb(facerig::test::DefaultHead(), "first"));
  const std::vector<char> second = ReadBytes(WriteHeadGlb(facerig::BuildDefaultHead(), "second"));
  REQUIRE(first.size() > 1000000);  // the textures are in it
  const bool identical = first == second;  // (Catch would print every byte)
  CHECK(identical);
}
