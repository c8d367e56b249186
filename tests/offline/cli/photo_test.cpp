// `facerig photo` on a real photograph shipped by Debian (python3-skimage's
// astronaut.png: NASA's portrait of Eileen Collins, public domain, 512 x 512):
// the landmarks land where a person marked the face by hand, the written
// texture holds the photo's skin on the cheeks, the GLB is validator-clean;
// and bad input (not an image, a face too small, no face) fails with a clear
// message and writes nothing.
#include <algorithm>
#include <functional>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <array>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli/app.h"
#include "command_report_check.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/photo/image.h"
#include "facerig/offline/photo/texture.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/part_roles.h"
#include "output_set_files.h"
#include "support/command_runner.h"
#include "support/default_head_poses.h"
#include "support/gltf_validator.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// Where python3-skimage (scripts/install-deps.sh) puts its sample photographs
// (found by CMake).
const fs::path kSkimageData = FACERIG_SAMPLE_PHOTOS_DIR;

fs::path SamplePhoto(const char* name) {
  const fs::path path = kSkimageData / name;
  if (!fs::exists(path)) FAIL(path << " is missing: install python3-skimage (scripts/install-deps.sh)");
  return path;
}

// Points marked by hand on astronaut.png (pixels, x right, y down): the
// centres of the eye openings (her right eye on the image's left), the nose
// tip and the middle of the open mouth.
constexpr glm::vec2 kImageLeftEye{203.0f, 101.0f}, kImageRightEye{246.0f, 102.5f};
constexpr glm::vec2 kNoseTip{223.0f, 127.5f}, kMouthCentre{224.0f, 145.0f};
// Cheek patches (x, y of the top-left corner; 8 x 8 px) below each eye,
// beside the nose, the skin lit evenly.
constexpr glm::ivec2 kImageLeftCheek{197, 118}, kImageRightCheek{240, 118};

glm::vec2 Mean(const nlohmann::json& landmarks, int first, int last) {
  glm::vec2 sum(0.0f);
  for (int i = first; i <= last; ++i) sum += glm::vec2(landmarks[i][0].get<float>(), landmarks[i][1].get<float>());
  return sum / static_cast<float>(last - first + 1);
}

void CheckLandmarksOnTheFace(const nlohmann::json& landmarks) {
  REQUIRE(landmarks.size() == 68);
  constexpr float kTolerance = 6.0f;  // pixels; dlib lands within about 3 of the marks
  CHECK(glm::distance(Mean(landmarks, 36, 41), kImageLeftEye) < kTolerance);
  CHECK(glm::distance(Mean(landmarks, 42, 47), kImageRightEye) < kTolerance);
  CHECK(glm::distance(Mean(landmarks, 30, 30), kNoseTip) < kTolerance);
  CHECK(glm::distance(Mean(landmarks, 60, 67), kMouthCentre) < kTolerance);
}

// Mean colour (levels) of a size x size patch.
glm::vec3 PatchMean(const RgbImage& image, glm::ivec2 corner, int size) {
  glm::vec3 sum(0.0f);
  for (int y = corner.y; y < corner.y + size; ++y) {
    for (int x = corner.x; x < corner.x + size; ++x) {
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x));
      sum += glm::vec3(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]);
    }
  }
  return sum / static_cast<float>(size * size);
}

// The photo's texture (the material the bake adds, or the one of another UV tile) on a written rig.
RgbImage PhotoSkinTexture(const Rig& rig, const std::string& name = "photo_skin") {
  for (const Material& material : rig.materials()) {
    if (material.name == name && material.base_colour_image >= 0) {
      return DecodeImage(rig.images()[static_cast<std::size_t>(material.base_colour_image)]);
    }
  }
  FAIL("the rig has no photo_skin material");
  return {};
}

// The texture's colour around vertex v's UV (5 x 5 texels).
glm::vec3 TextureAt(const Rig& rig, const RgbImage& texture, std::uint32_t v) {
  const glm::vec2 uv = rig.uvs()[v];
  const glm::ivec2 texel(static_cast<int>(uv.x * static_cast<float>(texture.width)) - 2,
                         static_cast<int>((1.0f - uv.y) * static_cast<float>(texture.height)) - 2);
  return PatchMean(texture, texel, 5);
}

// The texture at each cheek vertex holds the photo's cheek on that side
// (the light comes from her left: the sides differ by about 15 levels; over
// one cheek the skin varies by 40): per channel within `levels` of the
// patch's mean, and as red as the skin (red minus blue within 20 levels: not
// the grey background). `delit`: the photo's light was divided out, so each
// side is held to the mean of both patches instead of its own.
void CheckCheeks(const Rig& rig, std::uint32_t image_left_cheek, std::uint32_t image_right_cheek, float levels,
                 bool delit = false) {
  const RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  const RgbImage texture = PhotoSkinTexture(rig);
  const glm::vec3 both = 0.5f * (PatchMean(photo, kImageLeftCheek, 8) + PatchMean(photo, kImageRightCheek, 8));
  for (const auto& [v, patch] : {std::pair{image_left_cheek, kImageLeftCheek}, std::pair{image_right_cheek, kImageRightCheek}}) {
    const glm::vec3 skin = delit ? both : PatchMean(photo, patch, 8);
    const glm::vec3 baked = TextureAt(rig, texture, v);
    INFO("vertex " << v << ": baked " << baked.r << " " << baked.g << " " << baked.b << ", photo " << skin.r << " "
                   << skin.g << " " << skin.b);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(baked[c] - skin[c]) < levels);
    CHECK(std::abs((baked.r - baked.b) - (skin.r - skin.b)) < 20.0f);
  }
}

// Hair patches marked by hand on astronaut.png (12 x 12 px, top-left
// corners): the crown's lit top, the fringe, and both darker sides.
constexpr std::array<glm::ivec2, 4> kHairPatches{{{205, 28}, {215, 45}, {170, 60}, {270, 60}}};

glm::vec3 PhotoHairColour() {
  const RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  glm::vec3 sum(0.0f);
  for (const glm::ivec2 patch : kHairPatches) sum += PatchMean(photo, patch, 12);
  return sum / static_cast<float>(kHairPatches.size());
}

// The top of the head (the photo's skin parts above the eyes by over 60 % of
// the way to the crown) wears her hair: its median colour near the hand-marked
// hair's mean, and far darker than her cheeks (a bald head wore skin there).
void CheckScalpWearsTheHair(const Rig& rig, float eye_height) {
  float crown = eye_height;
  for (const glm::vec3& p : rig.positions()) crown = std::max(crown, p.y);
  std::vector<std::uint8_t> counted(rig.vertex_count(), 0);
  std::array<std::vector<float>, 3> channels;
  for (const Part& part : rig.parts()) {
    if (part.material < 0) continue;
    const std::string& name = rig.materials()[static_cast<std::size_t>(part.material)].name;
    if (name.rfind("photo_skin", 0) != 0) continue;
    const RgbImage texture = PhotoSkinTexture(rig, name);
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (const std::uint32_t v : rig.triangles()[t]) {
        if (counted[v] || rig.positions()[v].y < eye_height + 0.6f * (crown - eye_height)) continue;
        counted[v] = 1;
        const glm::vec3 colour = TextureAt(rig, texture, v);
        for (int c = 0; c < 3; ++c) channels[static_cast<std::size_t>(c)].push_back(colour[c]);
      }
    }
  }
  REQUIRE(channels[0].size() > 200);
  glm::vec3 scalp;
  for (int c = 0; c < 3; ++c) {
    auto& values = channels[static_cast<std::size_t>(c)];
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    scalp[c] = values[values.size() / 2];
  }
  const glm::vec3 hair = PhotoHairColour();
  const RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  const glm::vec3 cheek = PatchMean(photo, kImageLeftCheek, 8);
  INFO("scalp " << scalp.r << " " << scalp.g << " " << scalp.b << " over " << channels[0].size() << " vertices; hair "
                << hair.r << " " << hair.g << " " << hair.b << "; cheek " << cheek.r << " " << cheek.g << " " << cheek.b);
  for (int c = 0; c < 3; ++c) CHECK(std::abs(scalp[c] - hair[c]) < 35.0f);
  CHECK(scalp.g < cheek.g - 40.0f);
}

// The head mask of the plain photo: the hand-marked hair counts, the wall
// beside her hair and the flag do not; the hair colour lies near the marks'.
void CheckHairMask(const nlohmann::json& landmarks) {
  const RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  std::vector<glm::vec2> points;
  for (const auto& p : landmarks) points.emplace_back(p[0].get<float>(), p[1].get<float>());
  const PhotoHair hair = FindPhotoHair(photo, points, BuildPhotoSkinMask(photo, points));
  REQUIRE(hair.found);
  for (const glm::ivec2 patch : kHairPatches) CHECK(hair.head.At(patch.x + 6, patch.y + 6) > 0.9f);
  for (const glm::ivec2 wall : {glm::ivec2{120, 60}, glm::ivec2{330, 60}, glm::ivec2{320, 120}, glm::ivec2{225, 5}}) {
    INFO("wall at " << wall.x << ", " << wall.y);
    CHECK(hair.head.At(wall.x, wall.y) < 0.1f);
  }
  const glm::vec3 marked = PhotoHairColour(), found = 255.0f * hair.colour;
  INFO("hair colour " << found.r << " " << found.g << " " << found.b << ", marked " << marked.r << " " << marked.g << " " << marked.b);
  for (int c = 0; c < 3; ++c) CHECK(std::abs(found[c] - marked[c]) < 25.0f);
}

// The head's frame as the texture's scalp takes it: the eyes' centres (the
// eye parts' vertices either side of their midline), heights above them in
// eye spacings, azimuths (degrees) round a vertical axis 1.3 spacings behind.
struct HeadFrame {
  glm::vec3 eyes{0.0f}, across{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f}, forward{0.0f, 0.0f, 1.0f};
  float spacing = 1.0f;
  float Height(const glm::vec3& p) const { return glm::dot(p - eyes, up) / spacing; }
  float Azimuth(const glm::vec3& p) const {
    const glm::vec3 d = (p - eyes) / spacing;
    return std::atan2(glm::dot(d, across), glm::dot(d, forward) + 1.3f) * 57.29578f;
  }
};

HeadFrame FrameOf(const Rig& rig) {
  std::vector<std::uint32_t> eye;
  for (const Part& part : rig.parts()) {
    const PartRole role = RoleOfPart(part.name);
    if (role != PartRole::kSclera && role != PartRole::kIris && role != PartRole::kPupil) continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (const std::uint32_t v : rig.triangles()[t]) eye.push_back(v);
    }
  }
  REQUIRE(!eye.empty());
  float midline = 0.0f;
  for (const std::uint32_t v : eye) midline += rig.positions()[v].x / static_cast<float>(eye.size());
  glm::vec3 sum[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
  float count[2] = {0.0f, 0.0f};
  for (const std::uint32_t v : eye) {
    const int side = rig.positions()[v].x > midline ? 0 : 1;
    sum[side] += rig.positions()[v], count[side] += 1.0f;
  }
  REQUIRE((count[0] > 0.0f && count[1] > 0.0f));
  const glm::vec3 left = sum[0] / count[0], right = sum[1] / count[1];
  HeadFrame frame;
  frame.spacing = glm::distance(left, right);
  frame.eyes = 0.5f * (left + right);
  frame.across = (left - right) / frame.spacing;
  frame.up = glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) - frame.across * frame.across.y);
  frame.forward = glm::cross(frame.across, frame.up);
  return frame;
}

// The photo_skin texture's colour (levels) at each skin vertex `pick` takes.
std::vector<glm::vec3> PhotoSkinColours(const Rig& rig, const std::function<bool(const glm::vec3&)>& pick) {
  const RgbImage texture = PhotoSkinTexture(rig);
  std::vector<std::uint8_t> counted(rig.vertex_count(), 0);
  std::vector<glm::vec3> colours;
  for (const Part& part : rig.parts()) {
    if (part.material < 0 || rig.materials()[static_cast<std::size_t>(part.material)].name != "photo_skin") continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (const std::uint32_t v : rig.triangles()[t]) {
        if (counted[v] || !pick(rig.positions()[v])) continue;
        counted[v] = 1;
        colours.push_back(TextureAt(rig, texture, v));
      }
    }
  }
  return colours;
}

float Luma(const glm::vec3& c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; }

float MedianLuma(const std::vector<glm::vec3>& colours) {
  std::vector<float> lumas;
  for (const glm::vec3& c : colours) lumas.push_back(Luma(c));
  std::nth_element(lumas.begin(), lumas.begin() + static_cast<std::ptrdiff_t>(lumas.size() / 2), lumas.end());
  return lumas[lumas.size() / 2];
}

// The photo's cheeks (both hand-marked patches), levels.
glm::vec3 PhotoCheekColour() {
  const RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  return 0.5f * (PatchMean(photo, kImageLeftCheek, 8) + PatchMean(photo, kImageRightCheek, 8));
}

// The temples (below the hairline, beside the eyes, in front of the ears)
// wear skin: no texel there darker than the photo's cheeks by 60 levels of
// luma. A grey smudge of the fringe's shadow, taken at a grazing angle and
// spread by the fill, or of the hair spreading down from the scalp's soft
// edge, left texels 79-81 levels darker.
void CheckTemplesWearSkin(const Rig& rig) {
  const HeadFrame frame = FrameOf(rig);
  const std::vector<glm::vec3> temples = PhotoSkinColours(rig, [&](const glm::vec3& p) {
    const float height = frame.Height(p), azimuth = std::abs(frame.Azimuth(p));
    return height > 0.0f && height < 0.25f && azimuth > 55.0f && azimuth < 80.0f;
  });
  REQUIRE(temples.size() >= 10);
  float darkest = 255.0f;
  for (const glm::vec3& c : temples) darkest = std::min(darkest, Luma(c));
  const float cheek = Luma(PhotoCheekColour());
  INFO("darkest of " << temples.size() << " temple vertices: luma " << darkest << ", the photo's cheeks " << cheek);
  CHECK(darkest > cheek - 60.0f);
}

// The neck (which the photo does not show) meets the jaw without a band:
// just under the jaw its median luma within 20 levels of the jaw's underside
// (which the photo shows, in its shadow; a fill of the lit cheeks' colour was
// 23-28 levels lighter on the built-in head), and its hue the skin's: red
// minus blue over luma within 0.08 of the photo's cheeks'.
void CheckNeckMeetsTheJaw(const Rig& rig, float levels) {
  const HeadFrame frame = FrameOf(rig);
  const auto band = [&](float low, float high) {
    return PhotoSkinColours(rig, [&, low, high](const glm::vec3& p) {
      const float height = frame.Height(p);
      return height > low && height < high && std::abs(frame.Azimuth(p)) < 30.0f;
    });
  };
  const std::vector<glm::vec3> neck = band(-2.6f, -2.1f), jaw = band(-1.9f, -1.7f);
  REQUIRE((neck.size() >= 20 && jaw.size() >= 20));
  const float neck_luma = MedianLuma(neck), jaw_luma = MedianLuma(jaw);
  glm::vec3 neck_mean(0.0f);
  for (const glm::vec3& c : neck) neck_mean += c / static_cast<float>(neck.size());
  const glm::vec3 cheek = PhotoCheekColour();
  const float neck_redness = (neck_mean.r - neck_mean.b) / Luma(neck_mean), cheek_redness = (cheek.r - cheek.b) / Luma(cheek);
  INFO("neck luma " << neck_luma << " over " << neck.size() << " vertices, jaw " << jaw_luma << " over " << jaw.size()
                    << "; redness neck " << neck_redness << ", cheeks " << cheek_redness);
  CHECK(std::abs(neck_luma - jaw_luma) < levels);
  CHECK(std::abs(neck_redness - cheek_redness) < 0.08f);
}

// The photo's light taken out: the median luma of the texture over the face
// vertices within `radius` (cm) of each cheek vertex differs by less than
// `levels` between her two cheeks (about 15 with the photo's light in).
void CheckCheeksBalanced(const Rig& rig, std::uint32_t first, std::uint32_t second, float radius, float levels) {
  const auto around = [&](std::uint32_t centre) {
    return PhotoSkinColours(rig, [&, centre](const glm::vec3& p) {
      return glm::distance(p, rig.positions()[centre]) < radius;
    });
  };
  const std::vector<glm::vec3> one = around(first), other = around(second);
  REQUIRE((one.size() >= 20 && other.size() >= 20));
  const float difference = MedianLuma(one) - MedianLuma(other);
  INFO("cheek luma " << MedianLuma(one) << " over " << one.size() << " vertices, " << MedianLuma(other) << " over "
                     << other.size() << ": difference " << difference);
  CHECK(std::abs(difference) < levels);
}

// Her fringe comes down to about 0.55-0.6 eye spacings above the eyes'
// centres (measured on the photo, eye spacing 43 px, the fringe's edge 24-27
// px above the eyes at the middle): the hairline follows it in most azimuth
// bins round the front, not the eye-spacing rule's 1.05.
void CheckHairlineFromThePhoto(const nlohmann::json& texture) {
  INFO(texture.dump());
  CHECK(texture["hairline_bins_from_photo"].get<int>() >= 5);
  const double front = texture["hairline_front"].get<double>();
  CHECK(front > 0.4);
  CHECK(front < 0.8);
}

struct PhotoRun {
  fs::path out;
  test::CommandOutcome outcome;
  nlohmann::json report;
};

PhotoRun RunPhoto(const std::string& folder, const fs::path& image, const std::vector<std::string>& more = {}) {
  PhotoRun run{test::FreshOutputFolder(folder), {}, {}};
  std::vector<std::string> arguments{"photo",        image.string(),
                                     "-o",           (run.out / "head.glb").string(),
                                     "--frig",       (run.out / "head.frig").string(),
                                     "--json",       (run.out / "report.json").string(),
                                     "--debug-png",  (run.out / "fit.png").string()};
  arguments.insert(arguments.end(), more.begin(), more.end());
  run.outcome = test::RunCommand(cli::RunFacerig, arguments);
  if (run.outcome.exit_code == 0) run.report = nlohmann::json::parse(test::ReadText(run.out / "report.json"));
  return run;
}

// The outputs every successful run writes, and its report's steps.
void CheckWritten(const PhotoRun& run) {
  INFO(run.outcome.error_output);
  REQUIRE(run.outcome.exit_code == 0);
  test::CheckCommandReport(run.report, "photo");
  for (const char* step : {"read", "detect", "template", "fit", "texture", "write", "total"}) {
    CHECK(run.report["timings"].contains(step));
  }
  std::vector<std::string> names{"fit.png", "head.frig", "head.glb", "report.json"};
  if (fs::exists(run.out / "obj")) {
    names.insert(names.begin() + 3, "obj");
    CHECK(fs::exists(run.out / "obj" / "neutral.obj"));
    CHECK(fs::exists(run.out / "obj" / "materials.mtl"));
    CHECK(fs::exists(run.out / "obj" / "photo_skin.png"));
  }
  CHECK(test::Names(run.out) == names);
  test::RequireValidatorAccepts(run.out / "head.glb");
  // The stderr progress names each step.
  for (const char* line : {"detecting the face", "fitting the face", "baking the photo", "writing"}) {
    CHECK(run.outcome.error_output.find(line) != std::string::npos);
  }
}

// The astronaut in front of a saturated green wall: every pixel above her
// collar outside an ellipse round her face (her hair mostly gone) turned green.
constexpr glm::vec3 kGreen{40.0f, 200.0f, 60.0f};

fs::path GreenBackdropPhoto() {
  RgbImage photo = ReadPhoto(SamplePhoto("astronaut.png")).image;
  for (int y = 0; y < 200; ++y) {
    for (int x = 0; x < photo.width; ++x) {
      const float dx = (static_cast<float>(x) - 225.0f) / 52.0f, dy = (static_cast<float>(y) - 122.0f) / 66.0f;
      if (dx * dx + dy * dy <= 1.0f) continue;
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(photo.width) + static_cast<std::size_t>(x));
      for (int c = 0; c < 3; ++c) photo.pixels[i + static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(kGreen[c]);
    }
  }
  const fs::path path = test::FreshOutputFolder("cli_photo_green_input") / "astronaut_green.png";
  WritePng(path, photo);
  return path;
}

bool LooksGreen(const glm::vec3& colour) { return colour.g > std::max(colour.r, colour.b) + 30.0f; }

// The photo's texture at the skin vertices facing sideways or back (the
// head looks along +Z), which the photo's background lay next to.
void CheckNoBackdropOnTheSides(const Rig& rig) {
  const RgbImage texture = PhotoSkinTexture(rig);
  std::vector<std::uint8_t> counted(rig.vertex_count(), 0);
  std::size_t sides = 0, green = 0;
  for (const Part& part : rig.parts()) {
    if (part.material < 0 || rig.materials()[static_cast<std::size_t>(part.material)].name != "photo_skin") continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (const std::uint32_t v : rig.triangles()[t]) {
        if (counted[v] || rig.normals()[v].z > 0.2f) continue;
        counted[v] = 1;
        ++sides;
        green += LooksGreen(TextureAt(rig, texture, v)) ? 1 : 0;
      }
    }
  }
  INFO(green << " of " << sides << " side and back vertices textured green");
  REQUIRE(sides > 500);
  CHECK(static_cast<double>(green) < 0.002 * static_cast<double>(sides));
}

// The skin mask of the green photo: the cheeks count, the wall beside the
// face and the inside of her open mouth do not.
void CheckSkinMask(const fs::path& image, const nlohmann::json& landmarks) {
  const RgbImage photo = ReadPhoto(image).image;
  std::vector<glm::vec2> points;
  for (const auto& p : landmarks) points.emplace_back(p[0].get<float>(), p[1].get<float>());
  const PhotoSkinMask mask = BuildPhotoSkinMask(photo, points);
  for (const glm::ivec2 cheek : {kImageLeftCheek, kImageRightCheek}) CHECK(mask.At(cheek.x + 4, cheek.y + 4) > 0.9f);
  CHECK(mask.At(static_cast<int>(kMouthCentre.x), static_cast<int>(kMouthCentre.y)) < 0.05f);
  for (const int x : {160, 168, 282, 290}) CHECK(mask.At(x, 120) == 0.0f);
}

}  // namespace

TEST_CASE("facerig photo: the built-in head from a real photograph", "[cli][photo]") {
  const PhotoRun run = RunPhoto("cli_photo_head", SamplePhoto("astronaut.png"));
  CheckWritten(run);
  const nlohmann::json& result = run.report["result"];
  CHECK(result["template"]["built_in"] == true);
  CHECK(result["fit"]["deformed"] == true);
  CHECK(result["faces_found"] == 1);
  CheckLandmarksOnTheFace(result["landmarks"]);
  DefaultHeadFeatures features;
  const Rig& head = test::DefaultHead(&features);
  const Rig rig = LoadRig(run.out / "head.frig");
  CHECK(rig.vertex_count() >= head.vertex_count());
  CHECK(rig.FindShape("jawOpen").has_value());
  CHECK(rig.FindShape("viseme_aa").has_value());
  // The largest difference measured was 18 levels.
  CheckCheeks(rig, features.cheeks[1], features.cheeks[0], 25.0f);  // [0]: the character's left, the image's right
  CHECK(result["texture"]["hair_found"] == true);
  CheckHairMask(result["landmarks"]);
  CheckScalpWearsTheHair(rig, 0.5f * (features.eye_centres[0].y + features.eye_centres[1].y));
  CheckTemplesWearSkin(rig);
  CheckNeckMeetsTheJaw(rig, 20.0f);
  CheckHairlineFromThePhoto(result["texture"]);
  // Her mouth is open in the photo; the rest face's lips still meet as the
  // head's do (how far the mouth opens is an expression).
  float widest_gap = 0.0f;
  for (std::size_t i = 0; i < features.upper_lip.size(); ++i) {
    const float gap = glm::distance(rig.positions()[features.upper_lip[i]], rig.positions()[features.lower_lip[i]]);
    const float head_gap = glm::distance(head.positions()[features.upper_lip[i]], head.positions()[features.lower_lip[i]]);
    widest_gap = std::max(widest_gap, gap - head_gap);
  }
  INFO("widest lip gap beyond the head's own: " << widest_gap << " cm");
  CHECK(widest_gap < 0.15f);  // 0.09 cm; 0.26 when the photo's opening went into the rest face
}

TEST_CASE("facerig photo: ICT-FaceKit fitted with its identity modes (shared data)", "[cli][photo][shared-data]") {
  const PhotoRun run = RunPhoto("cli_photo_ict", SamplePhoto("astronaut.png"),
                                {"--template", test::IctDir().string(), "--obj-dir", (test::OutputPath("cli_photo_ict") / "obj").string()});
  REQUIRE(fs::exists(run.out / "obj"));
  CheckWritten(run);
  const nlohmann::json& result = run.report["result"];
  CHECK(result["template"]["built_in"] == false);
  CHECK(result["fit"]["identity_modes"] == 20);
  CHECK(result["fit"]["deformed"] == false);
  CheckLandmarksOnTheFace(result["landmarks"]);
  // ICT has a tongue but no tongueOut: the photo head gets one, as a built rig does.
  CHECK(result["tongue_out_synthesised_from"] == "gums_and_tongue");
  CHECK(result["shape_names"]["arkit_present"] == 52);
  CHECK(result["shape_names"]["arkit_missing"].empty());
  // The eyes got painted textures (ICT's are flat colours).
  CHECK(result["texture"]["eye_materials_painted"].get<int>() > 0);
  const Rig rig = LoadRig(run.out / "head.frig");
  // The cheeks: the face vertices nearest the middle of the shipped
  // descriptor's landmarks 1, 31, 41 (her right) and 15, 35, 46 (her left).
  const nlohmann::json descriptor =
      nlohmann::json::parse(test::ReadText(fs::path(FACERIG_SOURCE_DIR) / "data/templates/ict-facekit.template.json"));
  std::vector<std::uint32_t> cheeks;
  for (const auto& corners : {std::array{1, 31, 41}, std::array{15, 35, 46}}) {
    glm::vec3 centre(0.0f);
    for (const int k : corners) centre += rig.positions()[descriptor["landmarks"][k].get<std::uint32_t>()] / 3.0f;
    std::uint32_t nearest = 0;
    for (std::uint32_t v = 0; v < 9409; ++v) {  // ICT's face vertices
      if (glm::distance(rig.positions()[v], centre) < glm::distance(rig.positions()[nearest], centre)) nearest = v;
    }
    cheeks.push_back(nearest);
  }
  // The shading fit's light is divided out of the texture, so each cheek
  // vertex is held to the mean of both patches: 30 levels off at most (the
  // hand-marked patches are the cheeks' brightest skin; with the light in,
  // 28 from its own side's patch). Round the cheek vertices the two sides
  // are within 5.2 levels of each other (38 with the light in).
  CheckCheeks(rig, cheeks[0], cheeks[1], 32.0f, true);
  CheckCheeksBalanced(rig, cheeks[0], cheeks[1], 1.5f, 12.0f);
  // The back of ICT's head lies in a UV tile of its own (u in [1, 2]): it
  // gets a texture of its own and wears the hair, not the face's texels.
  CHECK(std::any_of(rig.materials().begin(), rig.materials().end(), [](const Material& m) { return m.name == "photo_skin_1_0"; }));
  float eye_height = 0.0f;
  for (int k = 36; k <= 47; ++k) eye_height += rig.positions()[descriptor["landmarks"][k].get<std::uint32_t>()].y / 12.0f;
  CheckScalpWearsTheHair(rig, eye_height);
  CheckTemplesWearSkin(rig);
  // With the photo's light divided out the jaw's underside is no longer in
  // her chin's shadow and the neck's fill is not darkened by it: 7.2 levels
  // apart (22.7 with the light in).
  CheckNeckMeetsTheJaw(rig, 12.0f);
  CheckHairlineFromThePhoto(result["texture"]);
}

TEST_CASE("facerig photo: a strongly coloured background stays off the head's sides and back", "[cli][photo]") {
  const fs::path image = GreenBackdropPhoto();
  const PhotoRun run = RunPhoto("cli_photo_green", image);
  INFO(run.outcome.error_output);
  REQUIRE(run.outcome.exit_code == 0);
  CheckSkinMask(image, run.report["result"]["landmarks"]);
  CheckNoBackdropOnTheSides(LoadRig(run.out / "head.frig"));
}

TEST_CASE("facerig photo: a grey-scale photo is converted, with a note", "[cli][photo]") {
  RgbImage grey = ReadPhoto(SamplePhoto("astronaut.png")).image;
  for (std::size_t i = 0; i < grey.pixels.size(); i += 3) {
    const auto level = static_cast<std::uint8_t>((grey.pixels[i] + grey.pixels[i + 1] + grey.pixels[i + 2]) / 3);
    grey.pixels[i] = grey.pixels[i + 1] = grey.pixels[i + 2] = level;
  }
  const fs::path image = test::FreshOutputFolder("cli_photo_grey_input") / "astronaut_grey.png";
  WritePng(image, grey);
  const PhotoRun run = RunPhoto("cli_photo_grey", image);
  REQUIRE(run.outcome.exit_code == 0);
  CHECK(run.report["result"]["photo"]["grey"] == true);
  CHECK(run.report["result"]["notes"].dump().find("grey-scale") != std::string::npos);
  CHECK(run.outcome.error_output.find("note: a grey-scale image") != std::string::npos);
}

TEST_CASE("facerig photo: bad input fails clearly and writes nothing", "[cli][photo]") {
  const fs::path inputs = test::FreshOutputFolder("cli_photo_bad_inputs");
  test::WriteText(inputs / "not_an_image.png", "hello, not a picture\n");
  // The astronaut at 120 px: her face is about 20 px, under dlib's 80 px window.
  WritePng(inputs / "tiny_face.png", ReadPhoto(SamplePhoto("astronaut.png"), {.max_side = 120}).image);
  struct Case {
    fs::path image;
    std::string message;
  };
  const std::vector<Case> cases = {
      {inputs / "not_an_image.png", "not_an_image.png: not a PNG or JPEG image"},
      {inputs / "missing.jpg", "missing.jpg"},
      {inputs / "tiny_face.png", "tiny_face.png: no face found (a frontal or near-frontal face of at least 80 px"},
      // Grey-scale, the cameraman in profile under his hat: dlib finds no face.
      {SamplePhoto("camera.png"), "camera.png: no face found"},
  };
  const fs::path out = test::FreshOutputFolder("cli_photo_bad");
  test::WriteText(out / "head.glb", "old head.glb");
  for (const Case& c : cases) {
    INFO(c.image);
    const test::CommandOutcome outcome = test::RunCommand(
        cli::RunFacerig, {"photo", c.image.string(), "-o", (out / "head.glb").string(), "--frig",
                          (out / "head.frig").string(), "--json", (out / "report.json").string()});
    CHECK(outcome.exit_code == 1);
    CHECK(outcome.error_output.find(c.message) != std::string::npos);
    INFO(outcome.error_output);
    CHECK(test::Names(out) == std::vector<std::string>{"head.glb"});
    CHECK(test::ReadText(out / "head.glb") == "old head.glb");
  }
}

}  // namespace facerig
