// Real assets: several meshes under nested node transforms, read as one rig
// in scene space, with morph targets of one name driven together.
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/io/atomic_file.h"
#include "facerig/runtime/io/gltf.h"
#include "support/base64.h"
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
