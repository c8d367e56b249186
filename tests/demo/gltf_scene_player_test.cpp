// The player takes a GLB as a DCC exports it: a head, a chin piece and a brow
// piece, each its own mesh with its own morph targets (names shared across
// meshes), in centimetres under an armature node that scales by 0.01, turns
// Z-up into Y-up and moves it. Rendered headless and compared with the same
// scene written with every transform already applied, in metres.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "facerig/runtime/io/rig_file.h"
#include "headless_player.h"
#include "media_writer.h"
#include "player_options.h"
#include "support/gltf_validator.h"
#include "support/scene_gltf.h"
#include "support/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using facerig::player::Image;
using facerig::test::SceneGltf;
using facerig::test::SceneMesh;

constexpr int kWidth = 160, kHeight = 120;
enum Piece { kHead, kChin, kBrow, kNone };
constexpr std::array<const char*, 3> kPieceNames = {"Head", "Chin", "Brow"};

// Every vertex of `mesh` for which `moved` holds gets `delta`.
template <typename Moved>
std::vector<glm::vec3> DeltasWhere(const SceneMesh& mesh, glm::vec3 delta, Moved moved) {
  std::vector<glm::vec3> deltas(mesh.positions.size(), glm::vec3(0.0f));
  for (std::size_t v = 0; v < deltas.size(); ++v) {
    if (moved(mesh.positions[v])) deltas[v] = delta;
  }
  return deltas;
}

// Authored Z up, facing -Y, in centimetres (as Blender's front view).
SceneGltf CentimetreScene() {
  SceneGltf scene;
  SceneMesh head{.name = "Head", .colour = {0.85f, 0.3f, 0.25f, 1.0f}};
  facerig::test::AddEllipsoid({0, 0, 0}, {8, 9, 11}, 14, 20, &head);
  head.targets = {{"jawOpen", DeltasWhere(head, {0, 0, -6}, [](glm::vec3 p) { return p.z < -3.0f; })},
                  {"eyeWide_L", DeltasWhere(head, {0, 0, 2}, [](glm::vec3 p) { return p.z > 5.0f; })}};
  SceneMesh chin{.name = "Chin", .colour = {0.25f, 0.8f, 0.3f, 1.0f}};
  facerig::test::AddQuad({-3, -3, -1.5f}, {6, 0, 0}, {0, 0, 3}, &chin);
  chin.targets = {{"jawOpen", DeltasWhere(chin, {0, 0, -8}, [](glm::vec3) { return true; })}};
  SceneMesh brow{.name = "Brow", .colour = {0.2f, 0.3f, 0.9f, 1.0f}};
  facerig::test::AddQuad({-6, -1, -0.75f}, {12, 0, 0}, {0, 0, 1.5f}, &brow);
  brow.targets = {{"eyeWide_L", DeltasWhere(brow, {0, 0, 2}, [](glm::vec3) { return true; })}};
  scene.meshes = {head, chin, brow};
  const glm::dquat z_up_to_y_up = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0));
  scene.nodes = {
      {.name = "Armature", .translation = {0.1, 1.4, -0.05}, .rotation = z_up_to_y_up, .scale = glm::dvec3(0.01),
       .children = {1}},
      {.name = "head", .translation = {2, 1, 160}, .rotation = glm::angleAxis(glm::radians(12.0), glm::dvec3(0, 0, 1)),
       .mesh = 0, .children = {2, 3}},
      {.name = "chin", .translation = {0, -7, -3}, .mesh = 1},
      {.name = "brow", .translation = {0, -9.5, 4}, .rotation = glm::angleAxis(glm::radians(5.0), glm::dvec3(0, 1, 0)),
       .mesh = 2},
  };
  scene.roots = {0};
  return scene;
}

// The same scene authored in metres: no 0.01 scale on the armature, every
// vertex, delta and node translation below it a hundredth as large.
SceneGltf MetreScene(SceneGltf scene) {
  scene.nodes[0].scale = glm::dvec3(1.0);
  for (std::size_t n = 1; n < scene.nodes.size(); ++n) scene.nodes[n].translation *= 0.01;
  for (SceneMesh& mesh : scene.meshes) {
    for (glm::vec3& p : mesh.positions) p *= 0.01f;
    for (auto& [name, deltas] : mesh.targets) {
      for (glm::vec3& d : deltas) d *= 0.01f;
    }
  }
  return scene;
}

facerig::Rig WrittenAndLoaded(const SceneGltf& scene, const std::string& name) {
  const fs::path path = facerig::test::OutputPath(name);
  facerig::test::WriteSceneGltf(path, scene);
  facerig::test::RequireValidatorAccepts(path);
  return facerig::LoadRig(path);
}

// Which piece a pixel shows, by its material's dominant channel (the
// background is a dark grey-blue that none of them matches).
Piece PieceAt(const Image& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 4;
  const int r = image.rgba[i], g = image.rgba[i + 1], b = image.rgba[i + 2];
  constexpr int kMargin = 40;
  if (r > std::max(g, b) + kMargin) return kHead;
  if (g > std::max(r, b) + kMargin) return kChin;
  if (b > std::max(r, g) + kMargin) return kBrow;
  return kNone;
}

struct Silhouette {
  int pixels = 0;
  int min_x = kWidth, min_y = kHeight, max_x = -1, max_y = -1;
};

Silhouette SilhouetteOf(const Image& image) {
  Silhouette s;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (PieceAt(image, x, y) == kNone) continue;
      ++s.pixels;
      s.min_x = std::min(s.min_x, x), s.max_x = std::max(s.max_x, x);
      s.min_y = std::min(s.min_y, y), s.max_y = std::max(s.max_y, y);
    }
  }
  return s;
}

// Pixels that show `piece` in one image and not in the other.
int PixelsChanged(const Image& a, const Image& b, Piece piece) {
  int changed = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) changed += (PieceAt(a, x, y) == piece) != (PieceAt(b, x, y) == piece);
  }
  return changed;
}

// Pixels that show `piece` in one image and the background in the other: its
// outline moved. Only its own shapes do that (the other pieces lie in front of it).
int OutlineChanged(const Image& a, const Image& b, Piece piece) {
  int changed = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const Piece in_a = PieceAt(a, x, y), in_b = PieceAt(b, x, y);
      changed += (in_a == piece && in_b == kNone) || (in_a == kNone && in_b == piece);
    }
  }
  return changed;
}

int PixelsOf(const Image& image, Piece piece) {
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) count += PieceAt(image, x, y) == piece;
  }
  return count;
}

}  // namespace

TEST_CASE("Player: a multi-mesh GLB in centimetres under a scaled, turned, moved armature", "[demo][gltf]") {
  const SceneGltf scene = CentimetreScene();
  const facerig::Rig rig = WrittenAndLoaded(scene, "player_scene_cm.glb");
  const facerig::Rig flat = WrittenAndLoaded(facerig::test::Flattened(scene), "player_scene_flat.glb");
  const facerig::Rig metres = WrittenAndLoaded(MetreScene(scene), "player_scene_m.glb");
  REQUIRE(rig.parts().size() == 3);
  REQUIRE(rig.vertex_count() == flat.vertex_count());
  // Metres: the head is 22 cm tall, whatever units the file's vertices are in.
  CHECK(rig.bounding_diagonal() == Approx(flat.bounding_diagonal()).epsilon(1e-4));
  CHECK(rig.bounding_diagonal() > 0.2f);
  CHECK(rig.bounding_diagonal() < 0.4f);
  // The chin's jawOpen, 8 cm down in its Z-up file, is 8 cm down in Y-up metres.
  const facerig::BlendShapeView jaw = rig.shape(*rig.FindShape("jawOpen"));
  const auto first_chin_vertex = static_cast<std::uint32_t>(scene.meshes[kHead].positions.size());  // meshes in order
  bool chin_delta_found = false;
  for (std::size_t i = 0; i < jaw.vertex_indices.size(); ++i) {
    if (jaw.vertex_indices[i] != first_chin_vertex) continue;
    chin_delta_found = true;
    CHECK(glm::distance(jaw.position_deltas[i], glm::vec3(0.0f, -0.08f, 0.0f)) < 1e-5f);
  }
  CHECK(chin_delta_found);

  SECTION("drawn as the scene in metres, and as the scene with its transforms applied") {
    const bool applied = GENERATE(false, true);
    INFO((applied ? "transforms applied" : "in metres"));
    const Image drawn = facerig::player::RenderNeutral(rig, kWidth, kHeight);
    const Image reference = facerig::player::RenderNeutral(applied ? flat : metres, kWidth, kHeight);
    facerig::player::WritePng(facerig::test::OutputPath("player_scene_cm.png"), drawn);
    facerig::player::WritePng(facerig::test::OutputPath(applied ? "player_scene_flat.png" : "player_scene_m.png"),
                              reference);
    const Silhouette s = SilhouetteOf(drawn), r = SilhouetteOf(reference);
    INFO("silhouette " << s.pixels << " px in [" << s.min_x << "," << s.max_x << "]x[" << s.min_y << "," << s.max_y
                       << "], reference " << r.pixels << " px in [" << r.min_x << "," << r.max_x << "]x[" << r.min_y
                       << "," << r.max_y << "]");
    const double fraction = static_cast<double>(s.pixels) / (kWidth * kHeight);
    CHECK(fraction > 0.15);
    CHECK(fraction < 0.85);
    for (auto [a, b] : {std::pair{s.min_x, r.min_x}, {s.max_x, r.max_x}, {s.min_y, r.min_y}, {s.max_y, r.max_y}}) {
      CHECK(std::abs(a - b) <= 2);
    }
    for (Piece piece : {kHead, kChin, kBrow}) {
      INFO(kPieceNames[piece] << ": " << PixelsOf(drawn, piece) << " px");
      CHECK(PixelsOf(drawn, piece) > 20);
      CHECK(PixelsChanged(drawn, reference, piece) <= PixelsOf(drawn, piece) / 20 + 4);
    }
  }

  SECTION("every mesh's morph targets move in the drawn frames") {
    const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_scene_surprise";
    facerig::player::PlayerOptions options;
    options.headless = true;
    options.still = true;
    options.emotions = {{facerig::Emotion::kSurprise, 1.0f}};  // jawOpen and eyeWide_L among others
    options.duration = 2.0;
    options.fps = 5.0;
    options.width = kWidth;
    options.height = kHeight;
    std::filesystem::create_directories(out);  // outputs' folders must exist
    options.frames_dir = out / "frames";
    std::ostringstream log;
    const facerig::player::HeadlessResult result = facerig::player::RunHeadless(rig, options, log);
    INFO(result.gl_description << "; " << log.str());
    REQUIRE(result.frames.size() == 10);
    const Image rest = facerig::player::RenderNeutral(rig, kWidth, kHeight);
    const Image first = facerig::player::ReadPng(result.frames.front());
    const Image surprised = facerig::player::ReadPng(result.frames.back());
    // The head's own shapes move its outline (jaw down, crown up); the chin
    // and brow, in front of it, change their own pixels.
    INFO("head outline: " << OutlineChanged(first, rest, kHead) << " px changed at frame 0, "
                          << OutlineChanged(surprised, rest, kHead) << " at the last");
    CHECK(OutlineChanged(first, rest, kHead) <= 2);
    CHECK(OutlineChanged(surprised, rest, kHead) > 20);
    for (Piece piece : {kChin, kBrow}) {
      INFO(kPieceNames[piece] << ": " << PixelsChanged(first, rest, piece) << " px changed at frame 0, "
                              << PixelsChanged(surprised, rest, piece) << " at the last, of " << PixelsOf(rest, piece));
      CHECK(PixelsChanged(first, rest, piece) <= 2);
      CHECK(PixelsChanged(surprised, rest, piece) > 20);
    }
  }
}
