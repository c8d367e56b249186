// The player draws a rig's own materials: textures through a GLB round trip
// (UV orientation, sRGB in and out), alpha blending over opaque parts, and
// the named-part colours for rigs whose materials say nothing. Rendered
// headless (EGL); the frames are written under the test output folder.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>
#include <glm/vec2.hpp>

#include "egl_context.h"
#include "face_renderer.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"
#include "gl_textures.h"
#include "headless_player.h"
#include "media_writer.h"
#include "measure/allocation_counter.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace {

using facerig::AlphaMode;
using facerig::RawRig;
using facerig::Rig;
using facerig::player::FaceRenderer;
using facerig::player::Image;

constexpr int kWidth = 200, kHeight = 200;
const glm::u8vec4 kRed{200, 40, 40, 255};
const glm::u8vec4 kBlue{40, 60, 200, 255};

Rig Build(RawRig raw) {
  std::string problem;
  auto rig = facerig::RigBuilder::Build(std::move(raw), &problem);
  if (!rig) FAIL("rig invalid: " << problem);
  return std::move(*rig);
}

// A 9x9 grid (8 cm square in the XY plane, facing +Z, UV (0,0) at its
// bottom-left) with a 2x2 red/blue checker, red at the image's top-left.
RawRig CheckerGridRaw() {
  RawRig raw = facerig::test::MakeGridRawRig(9, 0);
  raw.images.push_back(facerig::test::CheckerImage("checker.png", 64, 2, kRed, kBlue));
  facerig::Material material;
  material.name = "checker";
  material.base_colour_image = 0;
  raw.materials.push_back(material);
  for (facerig::RawPart& part : raw.parts) part.material = 0;
  return raw;
}

// Written as a GLB and read back, as a player would load it.
Rig ThroughGlb(const Rig& rig, const std::string& name) {
  const std::filesystem::path path = facerig::test::OutputPath(name + ".glb");
  facerig::WriteGltf(path, rig);
  return facerig::LoadRig(path);
}

// The rig at rest, saved as PNG under the test output folder; `inspect` sees
// the renderer before it goes away (for Project and problems).
template <typename Inspect>
Image Render(const Rig& rig, bool unlit, const std::string& png_name, Inspect inspect) {
  facerig::player::HeadlessGlContext context;
  FaceRenderer renderer(rig);
  renderer.set_unlit(unlit);
  facerig::player::OffscreenTarget target(kWidth, kHeight);
  renderer.Upload(rig.positions(), rig.normals());
  target.Bind();
  renderer.Draw(kWidth, kHeight, glm::mat4(1.0f));
  Image image;
  target.Read(&image);
  facerig::player::WritePng(facerig::test::OutputPath(png_name), image);
  inspect(renderer);
  return image;
}

Image Render(const Rig& rig, bool unlit, const std::string& png_name) {
  return Render(rig, unlit, png_name, [](const FaceRenderer&) {});
}

glm::u8vec4 PixelAt(const Image& image, glm::vec2 pixel) {
  const int x = std::clamp(static_cast<int>(pixel.x), 0, image.width - 1);
  const int y = std::clamp(static_cast<int>(pixel.y), 0, image.height - 1);
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 4;
  return {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2], image.rgba[i + 3]};
}

void CheckNear(glm::u8vec4 got, glm::u8vec4 expected, int tolerance) {
  INFO("got " << int(got.r) << "," << int(got.g) << "," << int(got.b) << " expected " << int(expected.r) << ","
              << int(expected.g) << "," << int(expected.b));
  for (int c = 0; c < 3; ++c) CHECK(std::abs(int(got[c]) - int(expected[c])) <= tolerance);
}

// Where the centres of the checker's cells project: top-left, top-right,
// bottom-left, bottom-right of the image (grid points at 2 and 6 cm).
std::array<glm::vec2, 4> CellCentres(const FaceRenderer& renderer) {
  return {renderer.Project({2, 6, 0}, kWidth, kHeight, glm::mat4(1.0f)),
          renderer.Project({6, 6, 0}, kWidth, kHeight, glm::mat4(1.0f)),
          renderer.Project({2, 2, 0}, kWidth, kHeight, glm::mat4(1.0f)),
          renderer.Project({6, 2, 0}, kWidth, kHeight, glm::mat4(1.0f))};
}

}  // namespace

TEST_CASE("Player materials: a GLB's checker texture lands upright with its sRGB colours", "[demo][materials]") {
  const Rig rig = ThroughGlb(Build(CheckerGridRaw()), "player_checker");
  REQUIRE(rig.materials().size() == 1);
  REQUIRE(rig.images().size() == 1);
  std::array<glm::vec2, 4> cells{};
  const Image unlit = Render(rig, true, "player_checker_unlit.png", [&](const FaceRenderer& renderer) {
    CHECK(renderer.problems().empty());
    cells = CellCentres(renderer);
  });
  // The camera looks at the face from +Z: the grid's top-left is the screen's top-left.
  REQUIRE(cells[0].x < cells[1].x);
  REQUIRE(cells[0].y < cells[2].y);
  // Unlit: the texel's sRGB value comes back (sampled linear, encoded again).
  CheckNear(PixelAt(unlit, cells[0]), kRed, 3);
  CheckNear(PixelAt(unlit, cells[1]), kBlue, 3);
  CheckNear(PixelAt(unlit, cells[2]), kBlue, 3);
  CheckNear(PixelAt(unlit, cells[3]), kRed, 3);

  const Image lit = Render(rig, false, "player_checker_lit.png");
  for (int i : {0, 3}) {
    const glm::u8vec4 red = PixelAt(lit, cells[i]);
    CHECK(red.r > red.b + 60);
  }
  for (int i : {1, 2}) {
    const glm::u8vec4 blue = PixelAt(lit, cells[i]);
    CHECK(blue.b > blue.r + 60);
  }
}

TEST_CASE("Player materials: blended parts draw after opaque ones, back to front", "[demo][materials]") {
  // Three quads facing +Z: an opaque red one at the back, then half-transparent
  // green and blue ones in front of it, listed front-most first so that the
  // part order is the wrong drawing order.
  RawRig raw;
  const auto add_quad = [&raw](float z, const char* name, glm::vec4 colour, AlphaMode mode) {
    const auto first = static_cast<std::uint32_t>(raw.positions.size());
    for (glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(4, 0), glm::vec2(4, 4), glm::vec2(0, 4)}) {
      raw.positions.emplace_back(corner, z);
    }
    const auto first_triangle = static_cast<std::uint32_t>(raw.triangles.size());
    raw.triangles.push_back({first, first + 1, first + 2});
    raw.triangles.push_back({first, first + 2, first + 3});
    facerig::Material material;
    material.name = name;
    material.base_colour = colour;
    material.alpha_mode = mode;
    raw.materials.push_back(material);
    raw.parts.push_back({name, first_triangle, 2, static_cast<std::int32_t>(raw.materials.size() - 1)});
  };
  add_quad(1.0f, "front", {0, 0, 1, 0.5f}, AlphaMode::kBlend);
  add_quad(0.5f, "middle", {0, 1, 0, 0.5f}, AlphaMode::kBlend);
  add_quad(0.0f, "back", {1, 0, 0, 1}, AlphaMode::kOpaque);
  raw.units = facerig::Units::kCentimetres;
  const Rig rig = ThroughGlb(Build(std::move(raw)), "player_blend");
  glm::vec2 centre{0.0f};
  const Image image = Render(rig, true, "player_blend_unlit.png", [&](const FaceRenderer& renderer) {
    centre = renderer.Project({2, 2, 0}, kWidth, kHeight, glm::mat4(1.0f));
  });
  // Red, then green over it, then blue over both (blended as encoded values).
  CheckNear(PixelAt(image, centre), {64, 64, 128, 255}, 4);
}

TEST_CASE("Player materials: placeholder materials (bare names, default greys) keep the named-part colours",
          "[demo][materials]") {
  RawRig named = facerig::test::MakeGridRawRig(9, 0);
  RawRig with_names = named;
  RawRig greys = named;  // ICT-FaceKit's MTL: Kd 0.6 and Ns 18 on the face
  RawRig coloured = named;
  with_names.materials.push_back(facerig::Material{.name = "M_Face"});
  greys.materials.push_back(facerig::Material{.name = "M_Face", .base_colour = {0.6f, 0.6f, 0.6f, 1.0f}, .roughness = 0.32f});
  coloured.materials.push_back(facerig::Material{.name = "green", .base_colour = {0.05f, 0.6f, 0.05f, 1.0f}});
  for (RawRig* raw : {&with_names, &greys, &coloured}) {
    for (facerig::RawPart& part : raw->parts) part.material = 0;
  }
  const Image before = Render(Build(named), false, "player_named_parts.png");
  const Image after = Render(Build(with_names), false, "player_name_only_materials.png");
  CHECK(before.rgba == after.rgba);
  CHECK(Render(Build(greys), false, "player_grey_materials.png").rgba == before.rgba);
  glm::vec2 centre{0.0f};
  const Image green = Render(Build(coloured), false, "player_green_material.png", [&](const FaceRenderer& renderer) {
    centre = renderer.Project({4, 4, 0}, kWidth, kHeight, glm::mat4(1.0f));
  });
  const glm::u8vec4 pixel = PixelAt(green, centre);
  CHECK(pixel.g > pixel.r + 60);
  CHECK(PixelAt(before, centre).r > PixelAt(before, centre).g);  // skin
}

TEST_CASE("Player materials: an image that does not decode is named, and its parts keep their colour",
          "[demo][materials]") {
  RawRig raw = CheckerGridRaw();
  raw.materials[0].base_colour = {0.05f, 0.6f, 0.05f, 1.0f};
  facerig::EncodedImage& image = raw.images[0];
  std::fill(image.bytes.begin() + 40, image.bytes.end(), std::uint8_t{0x5a});  // header kept, data garbage
  const Rig rig = Build(std::move(raw));
  cv::Mat rgba;
  std::string problem;
  CHECK_FALSE(facerig::player::DecodeRgba(rig.images()[0], &rgba, &problem));
  CHECK(problem.find("checker.png") != std::string::npos);

  glm::vec2 centre{0.0f};
  const Image frame = Render(rig, false, "player_bad_image.png", [&](const FaceRenderer& renderer) {
    REQUIRE(renderer.problems().size() == 1);
    CHECK(renderer.problems()[0].find("checker.png") != std::string::npos);
    centre = renderer.Project({4, 4, 0}, kWidth, kHeight, glm::mat4(1.0f));
  });
  const glm::u8vec4 pixel = PixelAt(frame, centre);
  CHECK(pixel.g > pixel.r + 60);

  // The headless player says so and renders on.
  facerig::player::PlayerOptions options;
  options.headless = true;
  options.frames_dir = facerig::test::FreshOutputFolder("player_bad_image") / "frames";
  options.width = 64, options.height = 48, options.fps = 10.0, options.duration = 0.1;
  std::ostringstream log;
  const facerig::player::HeadlessResult result = facerig::player::RunHeadless(rig, options, log);
  CHECK(result.frames.size() == 1);
  CHECK(log.str().find("warning: image \"checker.png\"") != std::string::npos);
}

TEST_CASE("Player materials: decoding checks the header's size and gives RGBA rows top first", "[demo][materials]") {
  facerig::EncodedImage image = facerig::test::CheckerImage("cells.png", 8, 2, kRed, kBlue);
  cv::Mat rgba;
  std::string problem;
  REQUIRE(facerig::player::DecodeRgba(image, &rgba, &problem));
  REQUIRE(rgba.type() == CV_8UC4);
  const cv::Vec4b top_left = rgba.at<cv::Vec4b>(0, 0), top_right = rgba.at<cv::Vec4b>(0, 7);
  CHECK(top_left == cv::Vec4b(kRed.r, kRed.g, kRed.b, kRed.a));
  CHECK(top_right == cv::Vec4b(kBlue.r, kBlue.g, kBlue.b, kBlue.a));
  image.width = 16;
  CHECK_FALSE(facerig::player::DecodeRgba(image, &rgba, &problem));
  CHECK(problem.find("cells.png") != std::string::npos);
  CHECK(problem.find("header says 16x8") != std::string::npos);
}

TEST_CASE("Player materials: drawing a textured, blended rig allocates nothing", "[demo][materials]") {
  RawRig raw = CheckerGridRaw();
  raw.materials[0].alpha_mode = AlphaMode::kBlend;
  raw.materials.push_back(facerig::Material{.name = "opaque", .base_colour = {0.5f, 0.5f, 0.5f, 1.0f}});
  raw.parts[1].material = 1;
  const Rig rig = Build(std::move(raw));
  facerig::player::HeadlessGlContext context;
  FaceRenderer renderer(rig);
  facerig::player::OffscreenTarget target(kWidth, kHeight);
  target.Bind();
  renderer.Upload(rig.positions(), rig.normals());
  renderer.Draw(kWidth, kHeight, glm::mat4(1.0f));  // the driver may allocate on first use
  facerig::test::AllocationCounter counter;
  for (int frame = 0; frame < 3; ++frame) {
    renderer.Upload(rig.positions(), rig.normals());
    renderer.Draw(kWidth, kHeight, glm::mat4(1.0f));
  }
  CHECK(counter.count() == 0);
}

TEST_CASE("Player materials: a normal map tilts the surface towards +u (red) and +v (green)", "[demo][materials]") {
  // The key light comes from the upper left: a surface tilted left or up is brighter.
  const auto brightness = [](glm::u8vec4 normal, const char* name) {
    RawRig raw = facerig::test::MakeGridRawRig(9, 0);
    raw.images.push_back(facerig::test::CheckerImage("normal.png", 16, 2, normal, normal));
    raw.materials.push_back(facerig::Material{.name = "bumpy", .base_colour = {0.5f, 0.5f, 0.5f, 1.0f},
                                              .normal_image = 0});
    for (facerig::RawPart& part : raw.parts) part.material = 0;
    glm::vec2 centre{0.0f};
    const Image image = Render(Build(std::move(raw)), false, std::string("player_normal_") + name + ".png",
                               [&](const FaceRenderer& renderer) {
                                 CHECK(renderer.problems().empty());
                                 centre = renderer.Project({4, 4, 0}, kWidth, kHeight, glm::mat4(1.0f));
                               });
    const glm::u8vec4 pixel = PixelAt(image, centre);
    return int(pixel.r) + int(pixel.g) + int(pixel.b);
  };
  // Normals (+-0.6, 0, 0.8) and (0, +-0.6, 0.8), encoded as n * 0.5 + 0.5.
  const int left = brightness({51, 128, 230, 255}, "left"), right = brightness({204, 128, 230, 255}, "right");
  const int up = brightness({128, 204, 230, 255}, "up"), down = brightness({128, 51, 230, 255}, "down");
  CHECK(left > right + 30);
  CHECK(up > down + 30);
}

TEST_CASE("Player materials: a masked material cuts out its transparent texels", "[demo][materials]") {
  RawRig raw = CheckerGridRaw();
  raw.images[0] = facerig::test::CheckerImage("cutout.png", 64, 2, kRed, glm::u8vec4(40, 60, 200, 0));
  raw.materials[0].alpha_mode = AlphaMode::kMask;
  raw.materials[0].alpha_cutoff = 0.5f;
  std::array<glm::vec2, 4> cells{};
  const Image image = Render(Build(std::move(raw)), true, "player_mask_unlit.png",
                             [&](const FaceRenderer& renderer) { cells = CellCentres(renderer); });
  const glm::u8vec4 background = PixelAt(image, {1.0f, 1.0f});
  CheckNear(PixelAt(image, cells[0]), kRed, 3);
  CheckNear(PixelAt(image, cells[3]), kRed, 3);
  CheckNear(PixelAt(image, cells[1]), background, 0);
  CheckNear(PixelAt(image, cells[2]), background, 0);
}
