#include "facerig/offline/render/rasterizer.h"
#include "support/test_meshes.h"
#include "facerig/offline/error.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

namespace {

// An orthographic front view of the square [-1, 1]^2 onto size x size pixels.
facerig::RasterView FrontView(int size) {
  return facerig::RasterView::Orbit({0.0f, 0.0f, 0.0f}, 1.0f, size, size);
}

}  // namespace

TEST_CASE("A single triangle gets its id and barycentrics", "[rasterizer]") {
  const std::vector<glm::vec3> positions = {{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {-1.0f, 1.0f, 0.0f}};
  const std::vector<facerig::Triangle> triangles = {{0, 1, 2}};
  const facerig::RasterView view = FrontView(64);
  const facerig::RasterBuffers buffers = facerig::Rasterize(facerig::test::MeshOf(positions, triangles), view);
  REQUIRE(buffers.width == 64);
  REQUIRE(buffers.height == 64);

  // Bottom-left pixel is inside, top-right is outside (the hypotenuse).
  CHECK(buffers.triangle_ids[buffers.index(0, 63)] == 0);
  CHECK(buffers.triangle_ids[buffers.index(63, 0)] == facerig::kNoTriangle);
  CHECK(buffers.back_facing[buffers.index(0, 63)] == 0);

  // Every covered pixel: barycentrics sum to 1 and reproduce the pixel centre.
  int covered = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const std::size_t i = buffers.index(x, y);
      if (buffers.triangle_ids[i] == facerig::kNoTriangle) continue;
      ++covered;
      const glm::vec3 b = buffers.barycentrics[i];
      REQUIRE(b.x + b.y + b.z == Approx(1.0f).margin(1e-5));
      glm::vec3 point;
      REQUIRE(buffers.SurfacePoint(x, y, facerig::test::MeshOf(positions, triangles), point));
      const glm::vec3 pixel = facerig::ProjectToImage(view, point);
      CHECK(pixel.x == Approx(x + 0.5).margin(1e-3));
      CHECK(pixel.y == Approx(y + 0.5).margin(1e-3));
    }
  }
  // Half the image, give or take the diagonal.
  CHECK(covered == Approx(64 * 64 / 2).margin(64));

  // A pixel near vertex 2 (top-left) weighs vertex 2 most.
  const glm::vec3 near_top_left = buffers.barycentrics[buffers.index(0, 0)];
  CHECK(near_top_left.z > 0.95f);
}

TEST_CASE("The nearer of two overlapping triangles wins, in either order", "[rasterizer]") {
  const std::vector<glm::vec3> positions = {
      {-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f},   // far
      {-1.0f, -1.0f, 0.5f}, {1.0f, -1.0f, 0.5f}, {0.0f, 1.0f, 0.5f}};  // near (+z faces the camera)
  for (const bool near_first : {false, true}) {
    const std::vector<facerig::Triangle> triangles =
        near_first ? std::vector<facerig::Triangle>{{3, 4, 5}, {0, 1, 2}}
                   : std::vector<facerig::Triangle>{{0, 1, 2}, {3, 4, 5}};
    const facerig::RasterBuffers buffers = facerig::Rasterize(facerig::test::MeshOf(positions, triangles), FrontView(32));
    const std::int32_t near_id = near_first ? 0 : 1;
    CHECK(buffers.triangle_ids[buffers.index(16, 20)] == near_id);
    CHECK(buffers.depths[buffers.index(16, 20)] == Approx(0.5f));
  }
}

TEST_CASE("Back faces are flagged and shaded dark", "[rasterizer]") {
  const std::vector<glm::vec3> positions = {{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  const std::vector<facerig::Triangle> clockwise = {{0, 2, 1}};
  const facerig::RasterView view = FrontView(16);
  const facerig::RasterBuffers buffers = facerig::Rasterize(facerig::test::MeshOf(positions, clockwise), view);
  const std::size_t centre = buffers.index(8, 9);
  REQUIRE(buffers.triangle_ids[centre] == 0);
  CHECK(buffers.back_facing[centre] == 1);
  const facerig::ShadeParams params;
  const facerig::RgbImage image = facerig::Shade(buffers, facerig::test::MeshOf(positions, clockwise), {}, view, params);
  CHECK(image.pixels[3 * centre] == static_cast<std::uint8_t>(std::lround(params.back_face.r * 255.0f)));

  // Front facing and lit from 30 degrees above the view axis: brighter.
  const std::vector<facerig::Triangle> front = {{0, 1, 2}};
  const facerig::RgbImage lit =
      facerig::Shade(facerig::Rasterize(facerig::test::MeshOf(positions, front), view), facerig::test::MeshOf(positions, front), {}, view, params);
  CHECK(lit.pixels[3 * centre] > 150);
  // Deterministic.
  const facerig::RgbImage again =
      facerig::Shade(facerig::Rasterize(facerig::test::MeshOf(positions, front), view), facerig::test::MeshOf(positions, front), {}, view, params);
  CHECK(lit.pixels == again.pixels);
}

TEST_CASE("Rasterize rejects bad views and indices", "[rasterizer]") {
  const std::vector<glm::vec3> positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  facerig::RasterView view = FrontView(8);
  view.width = 0;
  CHECK_THROWS_AS(facerig::Rasterize(facerig::test::MeshOf(positions, std::vector<facerig::Triangle>{{0, 1, 2}}), view),
                  facerig::InvalidInputError);
  CHECK_THROWS_AS(facerig::Rasterize(facerig::test::MeshOf(positions, std::vector<facerig::Triangle>{{0, 1, 3}}), FrontView(8)),
                  facerig::InvalidInputError);
}

TEST_CASE("A turned view keeps the image upright", "[rasterizer]") {
  // A point above the centre stays above it whatever the yaw.
  for (const float yaw : {-0.8f, 0.0f, 0.6f}) {
    const facerig::RasterView view = facerig::RasterView::Orbit({0.0f, 0.0f, 0.0f}, 1.0f, 100, 100, yaw);
    const glm::vec3 up = facerig::ProjectToImage(view, {0.0f, 0.5f, 0.0f});
    CHECK(up.x == Approx(50.0f));
    CHECK(up.y == Approx(25.0f));
  }
  // Yaw towards +x: a point on +x comes nearer the camera.
  const facerig::RasterView turned = facerig::RasterView::Orbit({0.0f, 0.0f, 0.0f}, 1.0f, 100, 100, 0.5f);
  CHECK(facerig::ProjectToImage(turned, {0.5f, 0.0f, 0.0f}).z > 0.0f);
}
