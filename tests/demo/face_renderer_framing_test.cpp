// The player's default framing (FaceRenderer::ResetCamera): the whole face,
// its chin included, at the default frame size.
#include "face_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <catch2/catch.hpp>
#include <glm/mat4x4.hpp>

#include "egl_context.h"
#include "facerig/runtime/io/rig_file.h"

TEST_CASE("Player: the default framing shows the built-in head from the top of its hair to below its chin at "
          "640x480, the jaw open too",
          "[demo]") {
  constexpr int kWidth = 640, kHeight = 480;
  const facerig::Rig rig = facerig::LoadRig(FACERIG_DEFAULT_HEAD);
  facerig::player::HeadlessGlContext context;
  const facerig::player::FaceRenderer renderer(rig);
  // The chin: the lowest point of the face's midline, in front of the neck.
  const auto jaw = rig.FindShape("jawOpen");
  REQUIRE(jaw);
  std::vector<glm::vec3> open(rig.positions().begin(), rig.positions().end());
  const facerig::BlendShapeView shape = rig.shape(*jaw);
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) open[shape.vertex_indices[i]] += shape.position_deltas[i];
  glm::vec3 chin(0.0f, 1e9f, 0.0f), chin_open(0.0f, 1e9f, 0.0f), top(0.0f, -1e9f, 0.0f);
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
    const glm::vec3 p = rig.positions()[v];
    if (p.y > top.y) top = p;
    if (std::abs(p.x) > 0.5f || p.z < 5.0f) continue;
    if (p.y < chin.y) chin = p;
    if (open[v].y < chin_open.y) chin_open = open[v];
  }
  const glm::mat4 still(1.0f);
  const float chin_row = renderer.Project(chin, kWidth, kHeight, still).y;
  const float open_row = renderer.Project(chin_open, kWidth, kHeight, still).y;
  const float top_row = renderer.Project(top, kWidth, kHeight, still).y;
  std::printf("default framing at %dx%d: top of the head at row %.0f, chin at row %.0f (jaw open %.0f)\n", kWidth,
              kHeight, static_cast<double>(top_row), static_cast<double>(chin_row), static_cast<double>(open_row));
  CHECK(top_row > 0.0f);
  CHECK(chin_row < 0.93f * kHeight);  // before: the frame ended at the lower lip, the chin below it
  CHECK(open_row < static_cast<float>(kHeight));
  // Still a portrait: the head fills most of the frame's height.
  CHECK(chin_row - top_row > 0.7f * kHeight);
}
