// Real assets: several meshes under nested node transforms, read as one rig
// in scene space, with morph targets of one name driven together.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/error.h"
#include "support/base64.h"
#include "support/gltf_validator.h"
#include "support/scene_gltf.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A .gltf built by hand: one buffer (a data URI), accessors added in order.
class HandMadeGltf {
 public:
  int AddVec3(const std::vector<glm::vec3>& values) {
    return Add(values.data(), values.size() * sizeof(glm::vec3), values.size(), 5126, "VEC3");
  }
  int AddIndices(const std::vector<std::uint16_t>& values) {
    return Add(values.data(), values.size() * sizeof(std::uint16_t), values.size(), 5123, "SCALAR");
  }
  json document = {{"asset", {{"version", "2.0"}}}, {"accessors", json::array()}, {"bufferViews", json::array()}};

  void Write(const fs::path& path) {
    document["buffers"] = {{{"byteLength", bytes_.size()},
                            {"uri", "data:application/octet-stream;base64," + test::Base64Encode(bytes_)}}};
    WriteFileAtomically(path, document.dump());
  }

 private:
  int Add(const void* data, std::size_t size, std::size_t count, int component, const char* type) {
    while (bytes_.size() % 4 != 0) bytes_.push_back(0);
    const std::size_t offset = bytes_.size();
    bytes_.resize(offset + size);
    std::memcpy(bytes_.data() + offset, data, size);
    document["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
    json accessor = {{"bufferView", document["bufferViews"].size() - 1}, {"componentType", component},
                     {"count", count}, {"type", type}};
    if (std::string(type) == "VEC3") {
      glm::vec3 lo(1e30f), hi(-1e30f);
      for (std::size_t i = 0; i < count; ++i) {
        lo = glm::min(lo, static_cast<const glm::vec3*>(data)[i]);
        hi = glm::max(hi, static_cast<const glm::vec3*>(data)[i]);
      }
      accessor["min"] = {lo.x, lo.y, lo.z};
      accessor["max"] = {hi.x, hi.y, hi.z};
    }
    document["accessors"].push_back(accessor);
    return static_cast<int>(document["accessors"].size()) - 1;
  }
  std::vector<unsigned char> bytes_;
};

// A head quad (shapes jawOpen, blink) and an eye triangle (shape blink) in
// centimetres, under a root node that scales by 0.01: both moved up 100 cm,
// the eye turned 90 degrees about +Y.
fs::path WriteTwoMeshScene() {
  HandMadeGltf gltf;
  const int head_positions = gltf.AddVec3({{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}});
  const int head_indices = gltf.AddIndices({0, 1, 2, 0, 2, 3});
  const int head_jaw = gltf.AddVec3({{0, 1, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
  const int head_blink = gltf.AddVec3({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 0, 0}});
  const int eye_positions = gltf.AddVec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int eye_indices = gltf.AddIndices({0, 1, 2});
  const int eye_blink = gltf.AddVec3({{0, 0, 0}, {0, 0, 0}, {0, 0, 1}});
  json& d = gltf.document;
  d["meshes"] = {
      {{"name", "Head"},
       {"primitives", {{{"attributes", {{"POSITION", head_positions}}}, {"indices", head_indices},
                        {"targets", {{{"POSITION", head_jaw}}, {{"POSITION", head_blink}}}}}}},
       {"extras", {{"targetNames", {"jawOpen", "blink"}}}}},
      {{"name", "Eye"},
       {"primitives", {{{"attributes", {{"POSITION", eye_positions}}}, {"indices", eye_indices},
                        {"targets", {{{"POSITION", eye_blink}}}}}}},
       {"extras", {{"targetNames", {"blink"}}}}}};
  const double half = std::sqrt(0.5);
  d["nodes"] = {{{"name", "root"}, {"scale", {0.01, 0.01, 0.01}}, {"children", {1, 2}}},
                {{"name", "head"}, {"translation", {0.0, 100.0, 0.0}}, {"mesh", 0}},
                {{"name", "eye"}, {"translation", {0.0, 100.0, 0.0}}, {"rotation", {0.0, half, 0.0, half}}, {"mesh", 1}}};
  d["scenes"] = {{{"nodes", {0}}}};
  d["scene"] = 0;
  const fs::path path = test::OutputPath("gltf_two_mesh_scene.gltf");
  gltf.Write(path);
  return path;
}

glm::vec3 DeltaOf(const Rig& rig, std::string_view shape_name, std::uint32_t vertex) {
  const BlendShapeView shape = rig.shape(*rig.FindShape(shape_name));
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    if (shape.vertex_indices[i] == vertex) return shape.position_deltas[i];
  }
  return glm::vec3(0.0f);
}

bool Near(glm::vec3 a, glm::vec3 b) { return glm::distance(a, b) < 1e-5f; }

}  // namespace

TEST_CASE("gltf scene: every mesh under nested node transforms, in metres, shapes driven by name across meshes",
          "[gltf]") {
  const Rig rig = ReadGltf(WriteTwoMeshScene());
  REQUIRE(rig.vertex_count() == 7);
  CHECK(rig.units() == Units::kMetres);
  REQUIRE(rig.parts().size() == 2);
  CHECK(rig.parts()[0].name == "Head");
  CHECK(rig.parts()[1].name == "Eye");
  // Scale 0.01 of (translation + position): the head's corner (10, 10, 0) cm is (0.1, 1.1, 0) m.
  CHECK(Near(rig.positions()[2], {0.1f, 1.1f, 0.0f}));
  // The eye turned about +Y: its (1, 0, 0) points along -Z.
  CHECK(Near(rig.positions()[4 + 1], {0.0f, 1.0f, -0.01f}));
  // One "blink" for both meshes, each delta turned and scaled as its mesh.
  REQUIRE(rig.shape_count() == 2);
  CHECK(Near(DeltaOf(rig, "jawOpen", 0), {0.0f, 0.01f, 0.0f}));
  CHECK(Near(DeltaOf(rig, "blink", 1), {0.01f, 0.0f, 0.0f}));
  CHECK(Near(DeltaOf(rig, "blink", 4 + 2), {0.01f, 0.0f, 0.0f}));
  CHECK(rig.bounding_diagonal() < 0.2f);  // a head 100 times too big was the bug
}

TEST_CASE("gltf scene: facerig's own files still read as they are", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 2);
  const fs::path path = test::OutputPath("gltf_scene_own.glb");
  WriteGltf(path, rig);
  const Rig back = ReadGltf(path);
  CHECK(back.vertex_count() == rig.vertex_count());
  CHECK(back.units() == rig.units());
  CHECK(std::equal(back.positions().begin(), back.positions().end(), rig.positions().begin()));
}

}  // namespace facerig

namespace facerig {
namespace {

using test::SceneGltf;
using test::SceneMesh;

// Blender's way: an armature object that scales by 0.01 and turns its Z up
// into glTF's Y up, two joints (root, jaw), and a mesh in centimetres whose
// node (a child of the armature, with a transform glTF says to ignore) is
// skinned: v0, v3 to the root, v1 to the jaw, v2 half and half. Inverse bind
// matrices from the armature's bind pose; the jaw then turned 30 degrees.
struct SkinnedScene {
  SceneGltf scene;
  glm::dmat4 root_skin{1.0}, jaw_skin{1.0};  // jointWorld x inverseBind, as the file poses them
};

SkinnedScene MakeSkinnedScene(bool jaw_turned) {
  SkinnedScene s;
  SceneMesh mesh{.name = "Face", .positions = {{-5, 0, 150}, {5, 0, 140}, {5, 0, 160}, {-5, 0, 160}},
                 .triangles = {{0, 1, 2}, {0, 2, 3}}};
  mesh.normals.assign(4, glm::vec3(0, -1, 0));  // facing -Y, Blender's front
  mesh.targets = {{"jawOpen", {{0, 0, 0}, {0, 0, -2}, {0, 0, 0}, {0, 0, 0}}}};
  mesh.target_normals = {{{0, 0, 0}, {0, 1, -1}, {0, 0, 0}, {0, 0, 0}}};  // turns v1's normal to -Z
  mesh.joints = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}};
  mesh.weights = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {1, 0, 0, 0}};
  s.scene.meshes = {mesh};
  s.scene.nodes = {
      {.name = "Armature", .translation = {0.0, 0.0, 0.3}, .rotation = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0)),
       .scale = glm::dvec3(0.01), .children = {1, 3}},
      {.name = "root", .translation = {0, 0, 100}, .children = {2}},
      {.name = "jaw", .translation = {0, -2, 45}},
      {.name = "Face", .translation = {7, 7, 7}, .mesh = 0, .skin = 0},
  };
  s.scene.roots = {0};
  const glm::dmat4 armature = test::NodeWorld(s.scene, 0);
  const glm::dmat4 root_bind = glm::inverse(test::NodeWorld(s.scene, 1)) * armature;
  const glm::dmat4 jaw_bind = glm::inverse(test::NodeWorld(s.scene, 2)) * armature;
  s.scene.skins = {{.joints = {1, 2}, .inverse_binds = {glm::mat4(root_bind), glm::mat4(jaw_bind)}}};
  if (jaw_turned) s.scene.nodes[2].rotation = glm::angleAxis(glm::radians(30.0), glm::dvec3(1, 0, 0));
  s.root_skin = test::NodeWorld(s.scene, 1) * glm::dmat4(glm::mat4(root_bind));
  s.jaw_skin = test::NodeWorld(s.scene, 2) * glm::dmat4(glm::mat4(jaw_bind));
  return s;
}

glm::vec3 Moved(const glm::dmat4& m, glm::vec3 p) { return glm::vec3(m * glm::dvec4(p, 1.0)); }

bool AllFinite(const Rig& rig) {
  auto finite = [](std::span<const glm::vec3> values) {
    return std::all_of(values.begin(), values.end(), [](glm::vec3 v) { return std::isfinite(v.x + v.y + v.z); });
  };
  return finite(rig.positions()) && finite(rig.normals()) && finite(rig.all_shape_position_deltas()) &&
         finite(rig.all_shape_normal_deltas());
}

}  // namespace

TEST_CASE("gltf scene: a skinned mesh at its bind pose under a 0.01, Z-up armature reads in metres, Y up",
          "[gltf]") {
  const SkinnedScene s = MakeSkinnedScene(false);
  const fs::path path = test::OutputPath("gltf_skinned_armature.glb");
  test::WriteSceneGltf(path, s.scene);
  test::RequireValidatorAccepts(path);
  const Rig rig = ReadGltf(path);
  REQUIRE(rig.vertex_count() == 4);
  // At the bind pose every vertex is where the armature puts the mesh: (x, y, z) cm -> (x, z, -y) / 100 m,
  // plus the armature's translation; the mesh node's own (7, 7, 7) is ignored.
  const glm::dmat4 armature = test::NodeWorld(s.scene, 0);
  for (std::uint32_t v = 0; v < 4; ++v) {
    INFO("vertex " << v);
    CHECK(Near(rig.positions()[v], Moved(armature, s.scene.meshes[0].positions[v])));
  }
  CHECK(Near(rig.positions()[2], {0.05f, 1.6f, 0.3f}));
  CHECK(rig.bounding_diagonal() == Approx(std::sqrt(0.1 * 0.1 + 0.2 * 0.2)).epsilon(1e-5));
  // Facing -Y in the file is facing +Z (glTF's front) in the scene; the jaw's 2 cm down is 2 cm down.
  CHECK(Near(rig.normals()[0], {0.0f, 0.0f, 1.0f}));
  CHECK(Near(DeltaOf(rig, "jawOpen", 1), {0.0f, -0.02f, 0.0f}));
  REQUIRE(rig.has_normal_deltas());
  // v1's normal turns from the scene's +Z to its -Y.
  CHECK(Near(rig.all_shape_normal_deltas()[0], glm::vec3(0.0f, -1.0f, 0.0f) - glm::vec3(0.0f, 0.0f, 1.0f)));
}

TEST_CASE("gltf scene: a skinned mesh follows its joints' current transforms, blended by its weights", "[gltf]") {
  const SkinnedScene s = MakeSkinnedScene(true);
  const fs::path path = test::OutputPath("gltf_skinned_jaw_turned.glb");
  test::WriteSceneGltf(path, s.scene);
  test::RequireValidatorAccepts(path);
  const Rig rig = ReadGltf(path);
  const std::vector<glm::vec3>& authored = s.scene.meshes[0].positions;
  CHECK(Near(rig.positions()[0], Moved(s.root_skin, authored[0])));
  CHECK(Near(rig.positions()[1], Moved(s.jaw_skin, authored[1])));
  CHECK(Near(rig.positions()[2], Moved(0.5 * s.root_skin + 0.5 * s.jaw_skin, authored[2])));
  CHECK(!Near(rig.positions()[1], Moved(s.root_skin, authored[1])));  // the jaw did turn it
  // The delta turns with the jaw (linear part) and stays in metres.
  CHECK(Near(DeltaOf(rig, "jawOpen", 1), glm::vec3(glm::dmat3(s.jaw_skin) * glm::dvec3(0, 0, -2))));
  CHECK(glm::length(DeltaOf(rig, "jawOpen", 1)) == Approx(0.02f).epsilon(1e-4));
}

TEST_CASE("gltf scene: a scale of 0 on a mesh node or a joint reads without NaNs", "[gltf]") {
  SECTION("a joint") {
    SkinnedScene s = MakeSkinnedScene(true);
    s.scene.nodes[2].scale = glm::dvec3(0.0);
    const fs::path path = test::OutputPath("gltf_skinned_jaw_scale0.glb");
    test::WriteSceneGltf(path, s.scene);
    const Rig rig = ReadGltf(path);
    CHECK(AllFinite(rig));
    // The jaw's vertex collapses onto the jaw; the root's stay where they were.
    CHECK(Near(rig.positions()[1], Moved(test::NodeWorld(s.scene, 2), glm::vec3(0.0f))));
    CHECK(Near(rig.positions()[0], Moved(s.root_skin, s.scene.meshes[0].positions[0])));
  }
  SECTION("a mesh node among others") {
    SkinnedScene s = MakeSkinnedScene(false);
    SceneGltf scene;
    SceneMesh mesh = s.scene.meshes[0];
    mesh.joints.clear();
    mesh.weights.clear();
    scene.meshes = {mesh, mesh};
    scene.nodes = {{.name = "shown", .scale = glm::dvec3(0.01), .mesh = 0},
                   {.name = "hidden", .scale = glm::dvec3(0.0), .mesh = 1}};
    scene.roots = {0, 1};
    const fs::path path = test::OutputPath("gltf_scene_scale0.glb");
    test::WriteSceneGltf(path, scene);
    const Rig rig = ReadGltf(path);
    REQUIRE(rig.vertex_count() == 8);
    CHECK(AllFinite(rig));
    CHECK(Near(rig.positions()[4], {0.0f, 0.0f, 0.0f}));
    CHECK(rig.normals()[4] == glm::vec3(0, -1, 0));  // a flattened mesh has no direction: its normals are kept
    // A node's scale of 0.01 leaves normal deltas changes of unit normals (v1 turns from -Y to -Z).
    const BlendShapeView jaw = rig.shape(*rig.FindShape("jawOpen"));
    REQUIRE(jaw.normal_deltas.size() == jaw.vertex_indices.size());
    const auto entry = std::find(jaw.vertex_indices.begin(), jaw.vertex_indices.end(), 1u);
    REQUIRE(entry != jaw.vertex_indices.end());
    CHECK(Near(jaw.normal_deltas[static_cast<std::size_t>(entry - jaw.vertex_indices.begin())], {0.0f, 1.0f, -1.0f}));
  }
}

TEST_CASE("gltf scene: malformed skins are refused naming the file and the field", "[gltf]") {
  SkinnedScene s = MakeSkinnedScene(true);
  std::string field;
  SECTION("a joint outside the skin") {
    s.scene.meshes[0].joints[1] = {7, 0, 0, 0};
    field = "JOINTS_0";
  }
  SECTION("a negative weight") {
    s.scene.meshes[0].weights[2] = {1.5f, -0.5f, 0, 0};
    field = "WEIGHTS_0";
  }
  SECTION("a weight that is not finite") {
    s.scene.meshes[0].weights[2] = {std::nanf(""), 0.5f, 0, 0};
    field = "WEIGHTS_0";
  }
  SECTION("a joint that is not a node") {
    s.scene.skins[0].joints[1] = 40;
    field = "joints[1]";
  }
  SECTION("fewer inverse bind matrices than joints") {
    s.scene.skins[0].inverse_binds.pop_back();
    field = "inverseBindMatrices";
  }
  const fs::path path = test::OutputPath("gltf_skinned_malformed.glb");
  test::WriteSceneGltf(path, s.scene);
  try {
    ReadGltf(path);
    FAIL("read a malformed skin");
  } catch (const IoError& e) {
    INFO(e.what());
    CHECK(e.path() == path.string());
    CHECK(std::string(e.what()).find(field) != std::string::npos);
  }
}

}  // namespace facerig

namespace facerig {

TEST_CASE("gltf scene: skin accessors outside their bufferView are refused", "[gltf]") {
  const fs::path path = test::OutputPath("gltf_skinned_outside.gltf");
  test::WriteSceneGltf(path, MakeSkinnedScene(true).scene);
  const std::vector<std::byte> bytes = ReadFileBytes(path);
  json document = json::parse(std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  const json& attributes = document["meshes"][0]["primitives"][0]["attributes"];
  std::string field;
  SECTION("JOINTS_0 past the end") {
    document["accessors"][attributes["JOINTS_0"].get<int>()]["byteOffset"] = 4096;
    field = "JOINTS_0";
  }
  SECTION("WEIGHTS_0 with a stride shorter than its elements") {
    document["bufferViews"][document["accessors"][attributes["WEIGHTS_0"].get<int>()]["bufferView"].get<int>()]
            ["byteStride"] = 4;
    field = "WEIGHTS_0";
  }
  SECTION("inverse bind matrices that are not MAT4") {
    document["accessors"][document["skins"][0]["inverseBindMatrices"].get<int>()]["type"] = "VEC4";
    field = "inverseBindMatrices";
  }
  WriteFileAtomically(path, document.dump());
  try {
    ReadGltf(path);
    FAIL("read a skin accessor outside its data");
  } catch (const IoError& e) {
    INFO(e.what());
    CHECK(e.path() == path.string());
    CHECK(std::string(e.what()).find(field) != std::string::npos);
  }
}

}  // namespace facerig
