#include "facerig/offline/render/eye_textures.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/io/obj.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

constexpr double kPi = std::numbers::pi;

// A unit sphere with an equirectangular UV map (a duplicated seam column):
// vertex (r, s) at theta = pi r / rings, phi = 2 pi s / segments, UV
// (s / segments, 1 - r / rings).
void AddUvSphere(Mesh& mesh, glm::vec3 centre, float radius, std::uint32_t part, std::uint32_t material) {
  constexpr int kRings = 48, kSegments = 96;
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  std::vector<glm::vec2> uvs;
  for (int r = 0; r <= kRings; ++r) {
    for (int s = 0; s <= kSegments; ++s) {
      const double theta = kPi * r / kRings, phi = 2.0 * kPi * s / kSegments;
      const glm::dvec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(centre + radius * glm::vec3(unit));
      uvs.emplace_back(static_cast<float>(s) / kSegments, 1.0f - static_cast<float>(r) / kRings);
    }
  }
  const auto at = [&](int r, int s) { return first + static_cast<std::uint32_t>(r * (kSegments + 1) + s); };
  for (int r = 0; r < kRings; ++r) {
    for (int s = 0; s < kSegments; ++s) {
      for (const Triangle& t : {Triangle{at(r, s), at(r + 1, s), at(r + 1, s + 1)},
                                Triangle{at(r, s), at(r + 1, s + 1), at(r, s + 1)}}) {
        mesh.triangles.push_back(t);
        for (std::uint32_t v : t) mesh.corner_uvs.push_back(uvs[v - first]);
        mesh.triangle_parts.push_back(part);
        mesh.triangle_materials.push_back(material);
      }
    }
  }
}

// An eyeball (part "sclera_L") looking along `forward` with a small iris
// mesh ("iris_L") inside it near its front, each with its own material; a
// third part `extra` (e.g. "pupil_L") when given.
Mesh Eye(glm::vec3 forward, const char* extra = nullptr) {
  Mesh mesh;
  mesh.part_names = {"sclera_L", "iris_L"};
  mesh.materials = {Material{.name = "sclera", .base_colour = glm::vec4(0.8f)},
                    Material{.name = "iris", .base_colour = glm::vec4(0.2f)}};
  AddUvSphere(mesh, glm::vec3(0.0f), 1.2f, 0, 0);
  AddUvSphere(mesh, 0.9f * glm::normalize(forward), 0.2f, 1, 1);
  if (extra != nullptr) {
    mesh.part_names.push_back(extra);
    AddUvSphere(mesh, 0.95f * glm::normalize(forward), 0.05f, 2, 1);
  }
  return mesh;
}

using Rgb = std::array<int, 3>;

// The texel of an image at a UV (OBJ's convention, v up).
Rgb Texel(const RgbImage& image, glm::vec2 uv) {
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(image.width)), 0, image.width - 1);
  const int y = std::clamp(static_cast<int>((1.0f - uv.y) * static_cast<float>(image.height)), 0, image.height - 1);
  const std::uint8_t* p = &image.pixels[3 * (static_cast<std::size_t>(y) * image.width + x)];
  return {p[0], p[1], p[2]};
}

RgbImage ImageOf(const Mesh& mesh, std::size_t material) {
  return DecodeImage(mesh.images.at(static_cast<std::size_t>(mesh.materials[material].base_colour_image)));
}

// The painted image's colour where the unit sphere's direction d lies in the
// equirectangular map.
Rgb ColourTowards(const Mesh& mesh, std::size_t material, glm::vec3 d) {
  const RgbImage image = ImageOf(mesh, material);
  d = glm::normalize(d);
  const double theta = std::acos(d.y);
  double phi = std::atan2(d.z, d.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  return Texel(image, glm::vec2(phi / (2.0 * kPi), 1.0 - theta / kPi));
}

}  // namespace

TEST_CASE("eye textures: an eyeball without a pupil part carries the iris and pupil round its forward axis",
          "[eye_textures]") {
  // Looking up and forward, so that a texture flipped in v puts the pupil
  // on the wrong side of the equator.
  const glm::vec3 forward = glm::normalize(glm::vec3(0.0f, 0.5f, 1.0f));
  Mesh eye = Eye(forward);
  REQUIRE(PaintEyeTextures(eye) == 2);
  CHECK(eye.materials[0].base_colour == glm::vec4(1.0f, 1.0f, 1.0f, 0.8f));  // alpha kept
  REQUIRE(eye.images.size() == 2);
  CHECK(eye.images[0].name == "sclera_painted.png");

  const Rgb pupil = ColourTowards(eye, 0, forward);
  CHECK(pupil[0] < 30);
  CHECK(pupil[2] < 30);
  // 0.35 rad off the axis: in the iris (half-angle 0.52), blue over red.
  const glm::vec3 side = glm::normalize(glm::cross(forward, glm::vec3(1, 0, 0)));
  const Rgb iris = ColourTowards(eye, 0, std::cos(0.35f) * forward + std::sin(0.35f) * side);
  CHECK(iris[2] > iris[0] + 20);
  CHECK(iris[2] < 160);
  // The back and the side of the eyeball: light sclera.
  for (const glm::vec3& away : {-forward, glm::vec3(1, 0, 0)}) {
    const Rgb sclera = ColourTowards(eye, 0, away);
    CHECK(sclera[0] > 180);
    CHECK(std::abs(sclera[0] - sclera[2]) < 30);
  }
  // The mirror of the pupil across the equator is sclera.
  const Rgb mirrored = ColourTowards(eye, 0, glm::vec3(forward.x, -forward.y, forward.z));
  CHECK(mirrored[0] > 180);
}

TEST_CASE("eye textures: with a pupil part the sclera stays white, and materials with images or shared with skin "
          "are left alone",
          "[eye_textures]") {
  Mesh eye = Eye(glm::vec3(0, 0, 1), "pupil_L");
  REQUIRE(PaintEyeTextures(eye) == 1);  // the iris material is shared with the pupil part
  CHECK(ColourTowards(eye, 0, glm::vec3(0, 0, 1))[0] > 180);
  CHECK(eye.materials[1].base_colour_image == -1);

  const std::size_t images = eye.images.size();
  CHECK(PaintEyeTextures(eye) == 0);  // already painted
  CHECK(eye.images.size() == images);

  Mesh no_uvs = Eye(glm::vec3(0, 0, 1));
  no_uvs.corner_uvs.clear();
  CHECK(PaintEyeTextures(no_uvs) == 0);

  Mesh broken = Eye(glm::vec3(0, 0, 1));
  broken.triangles[0][0] = 1u << 30;
  CHECK_THROWS_AS(PaintEyeTextures(broken), InvalidInputError);
}

TEST_CASE("(shared data) eye textures: ICT-FaceKit's eyeballs get a pupil where the iris mesh is", "[shared-data]") {
  Mesh ict = ReadObj(test::IctDir() / "generic_neutral_mesh.obj");
  REQUIRE(PaintEyeTextures(ict) == 5);  // M_ScleraLeft/Right, M_IrisLeft/Right and M_EyeLashes
  for (const char* side : {"M_ScleraLeft", "M_ScleraRight"}) {
    std::size_t material = 0;
    while (ict.materials[material].name != side) ++material;
    const RgbImage image = ImageOf(ict, material);
    // The darkest and lightest texels under the sclera's triangles: a pupil
    // and white sclera.
    int darkest = 255, lightest = 0;
    for (std::size_t t = 0; t < ict.triangle_count(); ++t) {
      if (ict.triangle_materials[t] != material) continue;
      glm::vec2 uv(0.0f);
      for (int k = 0; k < 3; ++k) uv += ict.corner_uvs[3 * t + static_cast<std::size_t>(k)] / 3.0f;
      uv -= glm::floor(uv);
      const int grey = Texel(image, uv)[1];
      darkest = std::min(darkest, grey);
      lightest = std::max(lightest, grey);
    }
    INFO(side);
    CHECK(darkest < 30);
    CHECK(lightest > 200);
  }
}

}  // namespace facerig
