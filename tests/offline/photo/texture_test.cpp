#include "facerig/offline/photo/texture.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_builder.h"
#include "support/default_head_poses.h"
#include "support/test_meshes.h"
#include "support/textured_assets.h"

namespace facerig {
namespace {

constexpr float kDegree = std::numbers::pi_v<float> / 180.0f;

glm::vec3 Texel(const RgbImage& image, int x, int y) {
  x = std::clamp(x, 0, image.width - 1), y = std::clamp(y, 0, image.height - 1);
  const std::uint8_t* c = &image.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x))];
  return {c[0], c[1], c[2]};
}

// The texture at `uv` (OBJ's v up), bilinear, in levels.
glm::vec3 SampleUv(const RgbImage& image, glm::vec2 uv) {
  const float x = uv.x * static_cast<float>(image.width) - 0.5f, y = (1.0f - uv.y) * static_cast<float>(image.height) - 0.5f;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float ax = x - std::floor(x), ay = y - std::floor(y);
  return glm::mix(glm::mix(Texel(image, x0, y0), Texel(image, x0 + 1, y0), ax),
                  glm::mix(Texel(image, x0, y0 + 1), Texel(image, x0 + 1, y0 + 1), ax), ay);
}

float ToSrgbLevel(float linear) {
  const float s = linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
  return 255.0f * std::clamp(s, 0.0f, 1.0f);
}

bool IsSkinPart(const Mesh& mesh, std::size_t t) { return RoleOfPart(mesh.part_names[mesh.triangle_parts[t]]) == PartRole::kSkin; }

// The mesh as a camera sees it with its textures (repeated), without the
// transparent layers over the eyes and the lashes: a photo with known albedo.
// Unlit, or lit by `light` (a factor at each surface point and its normal,
// interpolated from the vertices' as the bake does).
using Light = std::function<float(glm::vec3 point, glm::vec3 normal)>;
RgbImage RenderTextured(const Mesh& full, const RasterView& view, const Light& light = {}) {
  Mesh mesh = full;
  mesh.triangles.clear(), mesh.corner_uvs.clear(), mesh.triangle_parts.clear(), mesh.triangle_materials.clear();
  for (std::size_t t = 0; t < full.triangle_count(); ++t) {
    const PartRole role = RoleOfPart(full.part_names[full.triangle_parts[t]]);
    if (role == PartRole::kEyeLayer || role == PartRole::kLashes) continue;
    mesh.triangles.push_back(full.triangles[t]);
    for (int k = 0; k < 3; ++k) mesh.corner_uvs.push_back(full.corner_uvs[3 * t + static_cast<std::size_t>(k)]);
    mesh.triangle_parts.push_back(full.triangle_parts[t]);
    mesh.triangle_materials.push_back(full.triangle_materials[t]);
  }
  const RasterBuffers buffers = Rasterize(mesh, view);
  std::vector<glm::vec3> normals(full.vertex_count());
  ComputeVertexNormals(full.positions, full.triangles, normals);
  std::map<std::int32_t, RgbImage> decoded;
  for (const Material& m : mesh.materials) {
    if (m.base_colour_image >= 0 && !decoded.count(m.base_colour_image)) {
      decoded[m.base_colour_image] = DecodeImage(mesh.images[static_cast<std::size_t>(m.base_colour_image)]);
    }
  }
  RgbImage photo{view.width, view.height, std::vector<std::uint8_t>(3 * static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height), 40)};
  for (std::size_t i = 0; i < buffers.triangle_ids.size(); ++i) {
    const std::int32_t id = buffers.triangle_ids[i];
    if (id == kNoTriangle) continue;
    const auto t = static_cast<std::size_t>(id);
    const Material& m = mesh.materials[mesh.triangle_materials[t]];
    glm::vec3 colour(ToSrgbLevel(m.base_colour.r), ToSrgbLevel(m.base_colour.g), ToSrgbLevel(m.base_colour.b));
    if (m.base_colour_image >= 0) {
      const glm::vec3 b = buffers.barycentrics[i];
      const glm::vec2 uv = b.x * mesh.corner_uvs[3 * t] + b.y * mesh.corner_uvs[3 * t + 1] + b.z * mesh.corner_uvs[3 * t + 2];
      colour = SampleUv(decoded.at(m.base_colour_image), uv - glm::floor(uv));
    }
    glm::vec3 p(0.0f);
    if (light && buffers.SurfacePoint(static_cast<int>(i % static_cast<std::size_t>(view.width)),
                                      static_cast<int>(i / static_cast<std::size_t>(view.width)), mesh, p)) {
      const glm::vec3 b = buffers.barycentrics[i];
      const Triangle& v = mesh.triangles[t];
      const glm::vec3 n = glm::normalize(b.x * normals[v[0]] + b.y * normals[v[1]] + b.z * normals[v[2]]);
      colour = glm::min(colour * light(p, n), glm::vec3(255.0f));
    }
    for (int k = 0; k < 3; ++k) photo.pixels[3 * i + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(colour[k]));
  }
  return photo;
}

const Mesh& HeadMesh() {
  static const Mesh mesh = NeutralMesh(test::DefaultHead());
  return mesh;
}

// The portrait camera: the whole head, orthographic, turned by `yaw` (positive: towards the character's left).
RasterView Portrait(float yaw, int size = 768) { return RasterView::Orbit({0.0f, -1.5f, 0.0f}, 14.0f, size, size, yaw * kDegree); }

RgbImage SkinAlbedo(const Mesh& mesh) {
  for (const Material& m : mesh.materials) {
    if (m.name == "skin") return DecodeImage(mesh.images[static_cast<std::size_t>(m.base_colour_image)]);
  }
  FAIL("the head has no skin material");
  return {};
}

// Mean absolute difference (levels, over channels) between the bake and the
// source albedo over the texels `use` picks; and how many it picked.
std::pair<double, std::size_t> MeanError(const PhotoTexture& bake, const RgbImage& source,
                                         const std::function<bool(std::size_t)>& use) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
    if (!use(i)) continue;
    for (int k = 0; k < 3; ++k) sum += std::abs(int{bake.texture.pixels[3 * i + static_cast<std::size_t>(k)]} - int{source.pixels[3 * i + static_cast<std::size_t>(k)]});
    ++count;
  }
  return {count > 0 ? sum / (3.0 * static_cast<double>(count)) : 0.0, count};
}

// The baked texture as its material holds it, to look at.
void WriteBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

TEST_CASE("photo texture: a front render of the built-in head bakes back to its own albedo", "[photo_texture]") {
  const Mesh& mesh = HeadMesh();
  const RgbImage source = SkinAlbedo(mesh);
  const RasterView camera = Portrait(0.0f);
  const PhotoTexture bake = BakePhotoTexture(mesh, camera, RenderTextured(mesh, camera), {.size = source.width});
  REQUIRE(bake.texture.width == source.width);
  const auto [error, count] = MeanError(bake, source, [&](std::size_t i) { return bake.direct_weight[i] >= 0.99f; });
  INFO("front texels: " << count << ", mean error " << error << " levels");
  CHECK(count > bake.direct_weight.size() / 20);
  CHECK(error < 2.0);
  // The head is symmetric: its mirror partners lie close to the reflected vertices (cm).
  CHECK(bake.stats.mirror_pairs > 1000);
  CHECK(bake.stats.mirror_partner_error < 0.05);
  // The cheeks' colour, measured where the head's cheek vertices are.
  DefaultHeadFeatures features;
  test::DefaultHead(&features);
  const Rig& rig = test::DefaultHead();
  for (std::uint32_t cheek : features.cheeks) {
    const glm::vec3 truth = SampleUv(source, rig.uvs()[cheek]) / 255.0f;
    INFO("skin colour " << bake.skin_colour.r << " " << bake.skin_colour.g << " " << bake.skin_colour.b);
    CHECK(glm::length(bake.skin_colour - truth) < 0.08f);
  }
  WriteBytes(test::OutputPath("photo_texture_front.png"), bake.image.bytes);
}

TEST_CASE("photo texture: at 30 degrees the hidden side is filled from its mirror image, nothing left empty",
          "[photo_texture]") {
  const Mesh& mesh = HeadMesh();
  const RgbImage source = SkinAlbedo(mesh);
  const RasterView camera = Portrait(30.0f);
  const RgbImage photo = RenderTextured(mesh, camera);
  const PhotoTexture bake = BakePhotoTexture(mesh, camera, photo, {.size = source.width});
  const auto [seen_error, seen] = MeanError(bake, source, [&](std::size_t i) { return bake.direct_weight[i] >= 0.99f; });
  const auto [mirror_error, mirrored] = MeanError(bake, source, [&](std::size_t i) {
    return bake.direct_weight[i] == 0.0f && bake.mirror_weight[i] >= 0.99f;
  });
  INFO("seen " << seen << " texels, error " << seen_error << "; mirrored " << mirrored << ", error " << mirror_error);
  CHECK(seen_error < 2.0);
  // The painted albedo is symmetric but for its fine noise.
  CHECK(mirrored > bake.direct_weight.size() / 200);
  CHECK(mirror_error < 6.0);
  CHECK(bake.stats.mirrored_fraction > 0.0);
  // What neither side shows (the back of the head) takes about the skin
  // colour, and no texel is left unset (black).
  glm::dvec3 filled_sum(0.0);
  std::size_t filled = 0, black = 0;
  for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
    const glm::vec3 c = Texel(bake.texture, static_cast<int>(i % static_cast<std::size_t>(bake.texture.width)),
                              static_cast<int>(i / static_cast<std::size_t>(bake.texture.width)));
    black += c == glm::vec3(0.0f) ? 1 : 0;
    if (bake.direct_weight[i] > 0.0f || bake.mirror_weight[i] > 0.0f) continue;
    filled_sum += glm::dvec3(c) / 255.0;
    ++filled;
  }
  CHECK(black == 0);
  REQUIRE(filled > 0);
  const glm::vec3 filled_mean(filled_sum / static_cast<double>(filled));
  INFO("filled texels' mean " << filled_mean.r << " " << filled_mean.g << " " << filled_mean.b);
  CHECK(glm::length(filled_mean - bake.skin_colour) < 0.06f);
  WriteBytes(test::OutputPath("photo_texture_yaw30.png"), bake.image.bytes);
  WritePng(test::OutputPath("photo_texture_yaw30_coverage.png"), bake.coverage);
}

TEST_CASE("photo texture: a side lit brighter than the other does not brighten the mirrored texels",
          "[photo_texture]") {
  const Mesh& mesh = HeadMesh();
  const RgbImage source = SkinAlbedo(mesh);
  // The character's left (+X, towards the camera) lit 1.2, the right 0.8.
  const auto light = [](glm::vec3 p, glm::vec3) { return 1.0f + 0.2f * std::tanh(p.x / 0.5f); };
  const RasterView camera = Portrait(30.0f, 512);
  const PhotoTexture bake = BakePhotoTexture(mesh, camera, RenderTextured(mesh, camera, light), {.size = source.width});
  // Hidden texels (all on the right) should show the right side's light.
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
    if (bake.direct_weight[i] > 0.0f || bake.mirror_weight[i] < 0.99f) continue;
    for (std::size_t k = 0; k < 3; ++k) sum += std::abs(bake.texture.pixels[3 * i + k] - 0.8 * source.pixels[3 * i + k]);
    ++count;
  }
  REQUIRE(count > 1000);
  const double error = sum / (3.0 * static_cast<double>(count));
  INFO("mirrored texels: " << count << ", mean error against the right side's light " << error << " levels");
  CHECK(error < 8.0);
}

// Mean absolute difference (levels) between the bake and the source albedo
// times the gain that fits them best, over the texels `use` picks: the
// de-lit texture keeps the photo's overall brightness, not the albedo's.
double ScaledError(const PhotoTexture& bake, const RgbImage& source, const std::function<bool(std::size_t)>& use) {
  double cross = 0.0, square = 0.0;
  for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
    for (std::size_t k = 0; use(i) && k < 3; ++k) {
      cross += static_cast<double>(bake.texture.pixels[3 * i + k]) * source.pixels[3 * i + k];
      square += static_cast<double>(source.pixels[3 * i + k]) * source.pixels[3 * i + k];
    }
  }
  const double gain = square > 0.0 ? cross / square : 1.0;
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
    for (std::size_t k = 0; use(i) && k < 3; ++k, ++count) {
      sum += std::abs(bake.texture.pixels[3 * i + k] - gain * source.pixels[3 * i + k]);
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

TEST_CASE("photo texture: the photo's fitted light is divided out of the texture", "[photo_texture]") {
  const Mesh& mesh = HeadMesh();
  const RgbImage source = SkinAlbedo(mesh);
  const RasterView camera = Portrait(0.0f, 512);
  // Light from the character's left (+X) over an ambient, as spherical
  // harmonics of camera-space normals.
  PhotoLighting lighting{.coefficients = std::vector<glm::vec3>(9, glm::vec3(0.0f)), .rotation = camera.rotation};
  lighting.coefficients[0] = glm::vec3(0.7f), lighting.coefficients[1] = glm::vec3(0.25f);
  const auto light = [&](glm::vec3, glm::vec3 n) { return 0.7f + 0.25f * (camera.rotation * n).x; };
  const RgbImage photo = RenderTextured(mesh, camera, light);
  const PhotoTexture lit = BakePhotoTexture(mesh, camera, photo, {.size = source.width});
  const PhotoTexture delit = BakePhotoTexture(mesh, camera, photo, {.size = source.width}, {}, {}, lighting);
  const auto seen = [&](std::size_t i) { return delit.direct_weight[i] >= 0.99f; };
  const double lit_error = ScaledError(lit, source, seen), delit_error = ScaledError(delit, source, seen);
  INFO("front texels: mean error against the albedo " << lit_error << " levels lit, " << delit_error << " de-lit");
  CHECK(lit_error > 8.0);
  CHECK(delit_error < 3.0);
  // Switched off, the light stays in.
  PhotoTextureParams kept{.size = source.width};
  kept.delight = false;
  CHECK(ScaledError(BakePhotoTexture(mesh, camera, photo, kept, {}, {}, lighting), source, seen) > 8.0);
  WriteBytes(test::OutputPath("photo_texture_delit.png"), delit.image.bytes);
}

TEST_CASE("photo texture: applied, the skin shows the photo and eyes, teeth and mouth keep their materials",
          "[photo_texture]") {
  Mesh mesh = HeadMesh();
  const RasterView camera = Portrait(0.0f, 256);
  const PhotoTexture bake = BakePhotoTexture(mesh, camera, RenderTextured(mesh, camera), {.size = 128});
  const Mesh before = mesh;
  ApplyPhotoTexture(mesh, bake);
  std::string problem;
  REQUIRE(mesh.Validate(&problem));
  REQUIRE(ValidateMaterials(mesh.materials, mesh.images, &problem));
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Material& now = mesh.materials[mesh.triangle_materials[t]];
    if (IsSkinPart(mesh, t)) {
      REQUIRE(now.name == "photo_skin");
      REQUIRE(mesh.images[static_cast<std::size_t>(now.base_colour_image)].bytes == bake.image.bytes);
      continue;
    }
    const Material& was = before.materials[before.triangle_materials[t]];
    REQUIRE(now.name == was.name);
    REQUIRE(now.base_colour == was.base_colour);
    REQUIRE((now.base_colour_image < 0) == (was.base_colour_image < 0));
    if (was.base_colour_image >= 0) {
      REQUIRE(mesh.images[static_cast<std::size_t>(now.base_colour_image)].bytes ==
              before.images[static_cast<std::size_t>(was.base_colour_image)].bytes);
    }
  }
  // The old skin image is gone with the material that used it.
  CHECK(mesh.images.size() == before.images.size());
}

TEST_CASE("photo texture: a mesh wound the other way round bakes the same", "[photo_texture]") {
  const Mesh& head = HeadMesh();
  Mesh flipped = head;
  for (std::size_t t = 0; t < flipped.triangle_count(); ++t) {
    std::swap(flipped.triangles[t][1], flipped.triangles[t][2]);
    std::swap(flipped.corner_uvs[3 * t + 1], flipped.corner_uvs[3 * t + 2]);
    std::swap(flipped.corner_normals[3 * t + 1], flipped.corner_normals[3 * t + 2]);
  }
  const RasterView camera = Portrait(20.0f, 256);
  const RgbImage photo = RenderTextured(head, camera);
  const PhotoTexture a = BakePhotoTexture(head, camera, photo, {.size = 128});
  const PhotoTexture b = BakePhotoTexture(flipped, camera, photo, {.size = 128});
  REQUIRE(a.stats.seen_fraction > 0.2);
  CHECK(std::abs(a.stats.seen_fraction - b.stats.seen_fraction) < 1e-3);
  double difference = 0.0;
  for (std::size_t i = 0; i < a.texture.pixels.size(); ++i) difference += std::abs(int{a.texture.pixels[i]} - int{b.texture.pixels[i]});
  CHECK(difference / static_cast<double>(a.texture.pixels.size()) < 0.1);
}

TEST_CASE("photo texture: photo pixels outside the skin mask are taken neither directly nor mirrored",
          "[photo_texture]") {
  const Mesh& mesh = HeadMesh();
  const RasterView camera = Portrait(0.0f, 256);
  RgbImage photo = RenderTextured(mesh, camera);
  // The image's right half (the character's left) green, and masked out.
  PhotoSkinMask mask{0, 0, photo.width, photo.height, std::vector<float>(photo.pixels.size() / 3, 1.0f)};
  for (int y = 0; y < photo.height; ++y) {
    for (int x = photo.width / 2; x < photo.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(photo.width) + static_cast<std::size_t>(x);
      photo.pixels[3 * i] = 0, photo.pixels[3 * i + 1] = 255, photo.pixels[3 * i + 2] = 0;
      mask.weight[i] = 0.0f;
    }
  }
  const auto green_texels = [](const PhotoTexture& bake) {
    std::size_t green = 0;
    for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
      const glm::vec3 c = Texel(bake.texture, static_cast<int>(i % static_cast<std::size_t>(bake.texture.width)),
                                static_cast<int>(i / static_cast<std::size_t>(bake.texture.width)));
      green += c.g > std::max(c.r, c.b) + 40.0f ? 1 : 0;
    }
    return green;
  };
  const PhotoTexture unmasked = BakePhotoTexture(mesh, camera, photo, {.size = 256});
  const PhotoTexture masked = BakePhotoTexture(mesh, camera, photo, {.size = 256}, mask);
  INFO("green texels: " << green_texels(unmasked) << " unmasked, " << green_texels(masked) << " masked");
  CHECK(green_texels(unmasked) > 1000);
  CHECK(green_texels(masked) == 0);
  CHECK(masked.stats.seen_fraction < unmasked.stats.seen_fraction - 0.1);
  // A mask whose weights do not match its size is refused.
  PhotoSkinMask broken = mask;
  broken.weight.pop_back();
  CHECK_THROWS_AS(BakePhotoTexture(mesh, camera, photo, {.size = 64}, broken), InvalidInputError);
  PhotoHair broken_hair{broken, glm::vec3(0.5f), true};
  CHECK_THROWS_AS(BakePhotoTexture(mesh, camera, photo, {.size = 64}, mask, broken_hair), InvalidInputError);
  // The hair's head mask needs dlib's 68 landmarks.
  const std::vector<glm::vec2> too_few(10, glm::vec2(1.0f));
  CHECK_THROWS_AS(FindPhotoHair(photo, too_few, mask), InvalidInputError);
}

TEST_CASE("photo texture: invalid inputs are refused", "[photo_texture]") {
  const Mesh& head = HeadMesh();
  const RasterView camera = Portrait(0.0f, 64);
  const RgbImage photo{64, 64, std::vector<std::uint8_t>(64 * 64 * 3, 128)};
  Mesh no_uvs = head;
  no_uvs.corner_uvs.clear();
  CHECK_THROWS_AS(BakePhotoTexture(no_uvs, camera, photo), InvalidInputError);
  CHECK_THROWS_AS(BakePhotoTexture(head, Portrait(0.0f, 32), photo), InvalidInputError);
  CHECK_THROWS_AS(BakePhotoTexture(head, camera, RgbImage{64, 64, {}}), InvalidInputError);
  CHECK_THROWS_AS(BakePhotoTexture(head, camera, photo, {.size = 4}), InvalidInputError);
  CHECK_THROWS_AS(BakePhotoTexture(head, camera, photo, {.grazing_cos = 0.6f, .full_cos = 0.5f}), InvalidInputError);
  // A photo of the back of the head (no cheeks seen) still gives a full
  // texture, its skin colour what the photo shows.
  const PhotoTexture blank = BakePhotoTexture(head, Portrait(180.0f, 64), photo, {.size = 64});
  CHECK(blank.texture.pixels.size() == 64u * 64u * 3u);
  CHECK(glm::length(blank.skin_colour - glm::vec3(128.0f / 255.0f)) < 0.01f);
  CHECK(blank.stats.seen_fraction > 0.0);
}

TEST_CASE("photo texture: timing of a 1024 texture from a 1024 px photo", "[photo_texture][.measure]") {
  const Mesh& mesh = HeadMesh();
  const RasterView camera = Portrait(15.0f, 1024);
  const RgbImage photo = RenderTextured(mesh, camera);
  const auto start = std::chrono::steady_clock::now();
  const PhotoTexture bake = BakePhotoTexture(mesh, camera, photo);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN("bake 1024^2 from 1024 px: " << seconds << " s; seen " << bake.stats.seen_fraction << ", mirrored "
                                     << bake.stats.mirrored_fraction << ", filled " << bake.stats.filled_fraction
                                     << ", partner error " << bake.stats.mirror_partner_error << "; partners "
                                     << bake.stats.partner_seconds << " s, projection " << bake.stats.project_seconds
                                     << " s, fill " << bake.stats.fill_seconds << " s, PNG " << bake.stats.encode_seconds
                                     << " s (" << bake.image.bytes.size() << " bytes)");
  CHECK(bake.stats.seen_fraction > 0.0);  // speed is for facerig-bench to judge, not a test
}

}  // namespace facerig

namespace facerig {

TEST_CASE("(shared data) photo texture: ICT-FaceKit wearing a UV-coded albedo bakes back to that albedo",
          "[shared-data][photo_texture]") {
  Mesh ict = ReadObj(test::WriteTexturedIctIdentity(test::FreshOutputFolder("photo_texture_ict")));
  // The back of the head shares the face's UV space: it wears the albedo too.
  std::int32_t albedo = -1;
  for (const Material& m : ict.materials) albedo = m.name == "M_Face" ? m.base_colour_image : albedo;
  REQUIRE(albedo >= 0);
  for (Material& m : ict.materials) {
    if (m.name == "M_BackHead") m.base_colour_image = albedo, m.base_colour = glm::vec4(1.0f);
  }
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::size_t t = 0; t < ict.triangle_count(); ++t) {
    if (ict.part_names[ict.triangle_parts[t]] != "M_Face") continue;
    for (std::uint32_t v : ict.triangles[t]) lo = glm::min(lo, ict.positions[v]), hi = glm::max(hi, ict.positions[v]);
  }
  for (float yaw : {0.0f, 30.0f}) {
    const RasterView camera = RasterView::Orbit(0.5f * (lo + hi), 0.7f * (hi.y - lo.y), 768, 768, yaw * kDegree);
    const PhotoTexture bake = BakePhotoTexture(ict, camera, RenderTextured(ict, camera), {.size = 512});
    double error = 0.0;
    std::size_t count = 0;
    RgbImage error_image{512, 512, std::vector<std::uint8_t>(512 * 512 * 3, 0)};
    for (std::size_t i = 0; i < bake.direct_weight.size(); ++i) {
      if (bake.direct_weight[i] < 0.99f) continue;
      const int x = static_cast<int>(i % 512), y = static_cast<int>(i / 512);
      const glm::u8vec4 truth = test::UvCodedColour({(static_cast<float>(x) + 0.5f) / 512.0f, 1.0f - (static_cast<float>(y) + 0.5f) / 512.0f});
      const glm::vec3 baked = Texel(bake.texture, x, y);
      error += (std::abs(baked.r - truth.r) + std::abs(baked.g - truth.g)) / 2.0;
      for (int k = 0; k < 3; ++k) error_image.pixels[3 * i + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::min(255.0f, 8.0f * std::abs(baked[k] - truth[k])));
      ++count;
    }
    error /= static_cast<double>(std::max<std::size_t>(count, 1));
    INFO("ICT yaw " << yaw << ": " << count << " seen texels, mean error " << error << " levels; partners "
                    << bake.stats.mirror_pairs << ", partner error " << bake.stats.mirror_partner_error << "; seen "
                    << bake.stats.seen_fraction << ", mirrored " << bake.stats.mirrored_fraction << ", filled "
                    << bake.stats.filled_fraction);
    CHECK(count > 5000);
    CHECK(error < 1.5);
    const std::string name = "photo_texture_ict_yaw" + std::to_string(static_cast<int>(yaw));
    WriteBytes(test::OutputPath(name + ".png"), bake.image.bytes);
    WritePng(test::OutputPath(name + "_error_x8.png"), error_image);
  }
}

}  // namespace facerig
