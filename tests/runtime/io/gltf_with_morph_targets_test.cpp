#include "facerig/runtime/io/gltf_with_morph_targets.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/rig_builder.h"
#include "support/command_runner.h"
#include "support/gltf_validator.h"
#include "support/skinned_gltf.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A grid face and a separate little "eye" (its own vertex set), as two primitives.
std::vector<test::SkinnedPrimitive> FaceAndEye() {
  const RawRig grid = test::MakeGridRawRig(6, 0);
  test::SkinnedPrimitive face{grid.positions, grid.normals, grid.uvs, grid.triangles};
  for (glm::vec2& uv : face.uvs) uv.y = 1.0f - uv.y;
  face.normals.assign(face.positions.size(), glm::vec3(0, 0, 1));  // the grid lies in the XY plane
  test::SkinnedPrimitive eye;
  eye.positions = {{1, 1, 1}, {2, 1, 1}, {1.5f, 2, 1}, {1.5f, 1.5f, 1.5f}};
  eye.normals.assign(4, glm::vec3(0, 0, 1));
  eye.uvs = {{0, 0}, {1, 0}, {0.5f, 1}, {0.5f, 0.5f}};
  eye.triangles = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  return {face, eye};
}

// The rig read from `source` with two shapes (with normal deltas): one on the
// face only, one on the face and the eye.
Rig RigWithShapes(const fs::path& source) {
  RawRig raw = RigBuilder::ToRaw(ReadGltf(source));
  const auto vertex_count = static_cast<std::uint32_t>(raw.positions.size());
  RawBlendShape smile;
  smile.name = "mouthSmile_L";
  for (std::uint32_t v = 3; v < 20; v += 4) {
    smile.vertex_indices.push_back(v);
    smile.position_deltas.emplace_back(0.01f * static_cast<float>(v), 0.5f, -0.25f);
    smile.normal_deltas.emplace_back(0.0f, 0.1f, 0.0f);
  }
  RawBlendShape blink;
  blink.name = "eyeBlink_L";
  for (std::uint32_t v : {std::uint32_t{0}, vertex_count - 3, vertex_count - 1}) {
    blink.vertex_indices.push_back(v);
    blink.position_deltas.emplace_back(0.0f, -0.125f * static_cast<float>(v % 5 + 1), 0.0f);
    blink.normal_deltas.emplace_back(0.05f, 0.0f, 0.0f);
  }
  raw.shapes = {smile, blink};
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  INFO(problem);
  REQUIRE(rig);
  return std::move(*rig);
}

// glTF's default values, which a writer may leave out or spell out: the same
// document either way.
json WithoutDefaults(json value) {
  if (value.is_object()) {
    if (value.contains("mode") && value["mode"] == 4 && value.contains("attributes")) value.erase("mode");
    if (value.contains("texCoord") && value["texCoord"] == 0 && value.contains("index")) value.erase("texCoord");
    for (auto& [key, member] : value.items()) member = WithoutDefaults(member);
  } else if (value.is_array()) {
    for (json& element : value) element = WithoutDefaults(element);
  }
  return value;
}

// Every accessor of the source (attributes, indices, inverse bind matrices,
// animation keys) still holds the same elements in the output.
void RequireSameAccessors(const test::GltfFile& in, const test::GltfFile& out) {
  REQUIRE(out.document["accessors"].size() > in.document["accessors"].size());
  for (std::size_t a = 0; a < in.document["accessors"].size(); ++a) {
    INFO("accessor " << a);
    json before = in.document["accessors"][a], after = out.document["accessors"][a];
    CHECK(test::AccessorBytes(in, static_cast<int>(a)) == test::AccessorBytes(out, static_cast<int>(a)));
    for (json* accessor : {&before, &after}) {
      accessor->erase("bufferView");  // buffers may be merged or moved
      accessor->erase("byteOffset");
    }
    CHECK(before == after);
  }
}

void RequireSkinnedCharacterKept(const fs::path& source, const fs::path& output, const Rig& rig) {
  test::RequireValidatorAccepts(output);
  const test::GltfFile in = test::ReadGltfFile(source);
  const test::GltfFile out = test::ReadGltfFile(output);
  for (const char* kept : {"scene", "scenes", "nodes", "skins", "textures", "samplers", "animations",
                           "extensionsUsed", "materials"}) {
    INFO(kept << "\nbefore: " << in.document[kept].dump() << "\nafter: " << out.document[kept].dump());
    CHECK(WithoutDefaults(in.document[kept]) == WithoutDefaults(out.document[kept]));
  }
  RequireSameAccessors(in, out);
  REQUIRE(out.document["images"].size() == 1);
  CHECK(out.document["images"][0]["name"] == "skin colour");
  CHECK(out.document["images"][0]["mimeType"] == "image/png");
  const std::vector<unsigned char> png = test::ImageBytes(out, 0);
  CHECK(std::equal(png.begin(), png.end(), test::TexturePng().begin(), test::TexturePng().end()));

  const json& mesh_in = in.document["meshes"][0];
  const json& mesh = out.document["meshes"][0];
  CHECK(mesh["name"] == "face");
  CHECK(mesh["extras"]["artist"] == "kept");
  CHECK(mesh["extras"]["targetNames"] == json::array({"mouthSmile_L", "eyeBlink_L"}));
  CHECK(mesh["weights"] == json::array({0.0, 0.0}));
  REQUIRE(mesh["primitives"].size() == mesh_in["primitives"].size());
  for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
    json primitive = mesh["primitives"][p];
    REQUIRE(primitive["targets"].size() == 2);
    primitive.erase("targets");
    CHECK(WithoutDefaults(primitive) == WithoutDefaults(mesh_in["primitives"][p]));  // attributes, indices, material
  }

  // The shapes, read back, are the rig's: on the same vertices, bit for bit.
  const Rig back = ReadGltf(output);
  std::string difference;
  CHECK(test::RigsEqual(rig, back, 0.0f, &difference));
  INFO(difference);
  REQUIRE(back.has_normal_deltas());
  REQUIRE(back.all_shape_normal_deltas().size() == rig.all_shape_normal_deltas().size());
  for (std::size_t i = 0; i < rig.all_shape_normal_deltas().size(); ++i) {
    CHECK(back.all_shape_normal_deltas()[i] == rig.all_shape_normal_deltas()[i]);
  }
}

using test::NoTemporaryFilesIn;

}  // namespace

TEST_CASE("gltf with morph targets: a skinned character keeps its skin, nodes, material, texture and animation",
          "[gltf][gltf-validator]") {
  const fs::path folder = test::FreshOutputFolder("gltf_with_morph_targets");
  test::SkinnedGltfOptions options;
  options.with_lines = true;
  const std::string source_extension = GENERATE(std::string(".glb"), std::string(".gltf"));
  const std::string output_extension = GENERATE(std::string(".glb"), std::string(".gltf"));
  const fs::path source = folder / ("character" + source_extension);
  const fs::path output = folder / ("character_rig_from" + source_extension + output_extension);
  test::WriteSkinnedGltf(source, FaceAndEye(), options);
  test::RequireValidatorAccepts(source);
  const Rig rig = RigWithShapes(source);
  REQUIRE(rig.vertex_count() == 36 + 4);

  const MorphTargetsWritten written = WriteGltfWithMorphTargets(source, output, rig);
  CHECK(written.mesh_name == "face");
  CHECK(written.replaced_targets == 0);
  CHECK(written.embedded_images == (source_extension == ".gltf" ? 1u : 0u));  // the data-URI texture
  RequireSkinnedCharacterKept(source, output, rig);
  CHECK(NoTemporaryFilesIn(folder));

  SECTION("writing onto a file that already has morph targets replaces them") {
    const fs::path again = folder / ("again" + output_extension);
    const MorphTargetsWritten rewritten = WriteGltfWithMorphTargets(output, again, rig);
    CHECK(rewritten.replaced_targets == 2);
    test::RequireValidatorAccepts(again);
    std::string difference;
    CHECK(test::RigsEqual(rig, ReadGltf(again), 0.0f, &difference));
    INFO(difference);
  }
}

TEST_CASE("gltf with morph targets: onto facerig's own file, whose parts have their own, shared and out-of-order "
          "vertices",
          "[gltf]") {
  // The first part uses the highest vertices; the parts share a column.
  auto make_rig = [](float scale) {
    RawRig raw = test::MakeGridRawRig(6, 3, true);
    const auto half = static_cast<std::uint32_t>(raw.triangles.size() / 2);
    std::rotate(raw.triangles.begin(), raw.triangles.begin() + half, raw.triangles.end());
    raw.parts = {{"upper", 0, static_cast<std::uint32_t>(raw.triangles.size()) - half},
                 {"lower", static_cast<std::uint32_t>(raw.triangles.size()) - half, half}};
    for (RawBlendShape& shape : raw.shapes) {
      for (glm::vec3& delta : shape.position_deltas) delta *= scale;
    }
    std::string problem;
    std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
    INFO(problem);
    REQUIRE(rig);
    return std::move(*rig);
  };
  const fs::path source = test::OutputPath("gltf_morph_own_source.glb");
  const fs::path output = test::OutputPath("gltf_morph_own_output.glb");
  WriteGltf(source, make_rig(1.0f));
  const Rig rig = make_rig(2.0f);
  WriteGltfWithMorphTargets(source, output, rig);
  std::string difference;
  CHECK(test::RigsEqual(rig, ReadGltf(output), 0.0f, &difference));
  INFO(difference);
}

TEST_CASE("gltf with morph targets: a rig of another mesh is refused, and nothing is written", "[gltf]") {
  const fs::path folder = test::FreshOutputFolder("gltf_with_morph_targets_mismatch");
  const fs::path source = folder / "character.glb";
  test::WriteSkinnedGltf(source, FaceAndEye());
  const fs::path output = folder / "rig.glb";

  SECTION("a different vertex count names both counts") {
    try {
      WriteGltfWithMorphTargets(source, output, test::MakeGridRig(5, 2));
      FAIL("wrote a rig of 25 vertices onto a mesh of 40");
    } catch (const IoError& e) {
      INFO(e.what());
      CHECK(e.kind() == IoErrorKind::kTopologyMismatch);
      CHECK(e.path() == source.string());
      CHECK(std::string(e.what()).find("40 vertices") != std::string::npos);
      CHECK(std::string(e.what()).find("25") != std::string::npos);
      CHECK(std::string(e.what()).find("'face'") != std::string::npos);
    }
  }
  SECTION("a missing source") {
    try {
      WriteGltfWithMorphTargets(folder / "missing.glb", output, test::MakeGridRig(5, 2));
      FAIL("read a missing file");
    } catch (const IoError& e) {
      CHECK(e.kind() == IoErrorKind::kOpenFailed);
      CHECK(std::string(e.what()).find("missing.glb") != std::string::npos);
    }
  }
  SECTION("an output that is not glTF") {
    CHECK_THROWS_AS(WriteGltfWithMorphTargets(source, folder / "rig.fbx", RigWithShapes(source)), IoError);
  }
  CHECK_FALSE(fs::exists(output));
  CHECK(NoTemporaryFilesIn(folder));
}

}  // namespace facerig
