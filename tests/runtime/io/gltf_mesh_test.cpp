// glTF and the Mesh: ReadGltfMesh (UVs, normals, parts, materials) and
// WriteGltf with a surface mesh (UV seams split, materials, morph targets on
// the split vertices).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig_builder.h"
#include "support/gltf_validator.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// The grid rig's neutral with UVs per corner: the right half's shifted by
// 0.5 in u, so the column where the halves meet is a seam; materials "skin"
// (left, and the last triangle) and "lens" (right).
Mesh SeamedSurface(const Rig& rig) {
  Mesh surface = NeutralMesh(rig);
  const std::size_t half = surface.triangle_count() / 2;
  for (std::size_t t = half; t < surface.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) surface.corner_uvs[t * 3 + c].x += 0.5f;
  }
  surface.materials = {Material{.name = "skin",
                                .base_colour = {0.8f, 0.6f, 0.5f, 1.0f},
                                .base_colour_image = 0,
                                .normal_image = 1},
                       Material{.name = "lens",
                                .base_colour = {1.0f, 1.0f, 1.0f, 0.25f},
                                .alpha_mode = AlphaMode::kMask,
                                .alpha_cutoff = 0.3f,
                                .double_sided = true}};
  surface.images = {test::CheckerImage("skin.png", 8, 2, {200, 150, 120, 255}, {90, 40, 30, 255}),
                    test::CheckerImage("skin_normal.png", 4, 1, {128, 128, 255, 255}, {128, 128, 255, 255})};
  surface.triangle_materials.assign(surface.triangle_count(), 0);
  for (std::size_t t = half; t + 1 < surface.triangle_count(); ++t) surface.triangle_materials[t] = 1;
  return surface;
}

// Dense position deltas of shape `s` at vertex `v`.
glm::vec3 DeltaAt(const Rig& rig, std::size_t s, std::uint32_t v) {
  const BlendShapeView shape = rig.shape(s);
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    if (shape.vertex_indices[i] == v) return shape.position_deltas[i];
  }
  return glm::vec3(0.0f);
}

}  // namespace

TEST_CASE("gltf mesh: a rig written with a seamed, two-material surface reads back as that mesh", "[gltf]") {
  const Rig rig = test::MakeGridRig(5, 3, true);
  const Mesh surface = SeamedSurface(rig);
  const fs::path path = test::OutputPath("gltf_mesh_seams.glb");
  WriteGltf(path, rig, surface);

  const Mesh back = ReadGltfMesh(path);
  std::string problem;
  REQUIRE(back.Validate(&problem));
  // The rig's vertices first, then one copy per seam vertex (the 5 of the middle column).
  REQUIRE(back.vertex_count() == rig.vertex_count() + 5);
  REQUIRE(back.triangle_count() == rig.triangle_count());
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) CHECK(back.positions[v] == rig.positions()[v]);
  REQUIRE(back.corner_uvs.size() == surface.corner_uvs.size());
  for (std::size_t t = 0; t < back.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      CHECK(back.positions[back.triangles[t][c]] == rig.positions()[rig.triangles()[t][c]]);
      CHECK(back.corner_uvs[t * 3 + c].x == Approx(surface.corner_uvs[t * 3 + c].x).margin(1e-6));
      CHECK(back.corner_uvs[t * 3 + c].y == Approx(surface.corner_uvs[t * 3 + c].y).margin(1e-6));
    }
  }
  // One part per primitive: a primitive per run of one part and one material.
  CHECK(back.part_names == std::vector<std::string>{"left", "right", "right"});
  CHECK(back.triangle_materials == surface.triangle_materials);
  REQUIRE(back.materials.size() == 2);
  CHECK(back.materials[0].name == "skin");
  CHECK(back.materials[0].base_colour == surface.materials[0].base_colour);
  // The images are embedded as they were, byte for byte.
  REQUIRE(back.images.size() == 2);
  REQUIRE(back.materials[0].base_colour_image == 0);
  REQUIRE(back.materials[0].normal_image == 1);
  CHECK(back.images[0].name == "skin.png");
  CHECK(back.images[0].bytes == surface.images[0].bytes);
  CHECK(back.images[0].width == 8);
  CHECK(back.images[1].bytes == surface.images[1].bytes);
  CHECK(back.materials[0].alpha_mode == AlphaMode::kOpaque);
  CHECK_FALSE(back.materials[0].double_sided);
  CHECK(back.materials[1].name == "lens");
  CHECK(back.materials[1].base_colour == surface.materials[1].base_colour);
  CHECK(back.materials[1].base_colour_image == -1);
  CHECK(back.materials[1].alpha_mode == AlphaMode::kMask);
  CHECK(back.materials[1].alpha_cutoff == Approx(0.3f));
  CHECK(back.materials[1].double_sided);

  // A copy moves and turns as its vertex does.
  const Rig read = ReadGltf(path);
  REQUIRE(read.shape_count() == rig.shape_count());
  // The rig carries the materials too: each part names its own.
  REQUIRE(read.materials().size() == 2);
  REQUIRE(read.images().size() == 2);
  REQUIRE(read.parts().size() == 3);
  CHECK(read.parts()[0].material == 0);
  CHECK(read.parts()[1].material == 1);
  CHECK(read.parts()[2].material == 0);
  CHECK(read.images()[0].bytes == surface.images[0].bytes);
  REQUIRE(read.has_normal_deltas());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    for (std::size_t t = 0; t < rig.triangle_count(); ++t) {
      for (std::size_t c = 0; c < 3; ++c) {
        const std::uint32_t v = read.triangles()[t][c];
        CHECK(DeltaAt(read, s, v) == DeltaAt(rig, s, rig.triangles()[t][c]));
        CHECK(read.normals()[v] == rig.normals()[rig.triangles()[t][c]]);
      }
    }
  }
  Mesh from_read;
  CHECK(ReadGltf(path, &from_read).vertex_count() == back.vertex_count());
  CHECK(from_read.corner_uvs == back.corner_uvs);
  CHECK(from_read.part_names == back.part_names);
}

TEST_CASE("gltf mesh: a surface without seams or materials writes the rig's own file", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 2, false);
  // The same file name (it names the mesh and node) in three folders.
  const fs::path folder = test::FreshOutputFolder("gltf_mesh_same_bytes");
  for (const char* sub : {"alone", "with_uvs", "bare"}) fs::create_directories(folder / sub);
  const fs::path alone = folder / "alone" / "head.glb";
  const fs::path with_uvs = folder / "with_uvs" / "head.glb";
  const fs::path bare = folder / "bare" / "head.glb";
  WriteGltf(alone, rig);
  WriteGltf(with_uvs, rig, NeutralMesh(rig));  // per-vertex UVs: no seam
  Mesh no_uvs = NeutralMesh(rig);
  no_uvs.corner_uvs.clear();
  WriteGltf(bare, rig, no_uvs);
  CHECK(ReadFileBytes(with_uvs) == ReadFileBytes(alone));
  CHECK(ReadFileBytes(bare) == ReadFileBytes(alone));
}

TEST_CASE("gltf mesh: a surface that is not on the rig is refused", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 1, false);
  Mesh surface = SeamedSurface(rig);
  std::swap(surface.triangles[0], surface.triangles[1]);
  const fs::path path = test::OutputPath("gltf_mesh_mismatch.glb");
  fs::remove(path);
  try {
    WriteGltf(path, rig, surface);
    FAIL("no error");
  } catch (const IoError& error) {
    CHECK(error.kind() == IoErrorKind::kWriteFailed);
  }
  surface = SeamedSurface(rig);
  surface.triangle_materials[0] = 7;
  CHECK_THROWS_AS(WriteGltf(path, rig, surface), IoError);
  CHECK_FALSE(fs::exists(path));
}

TEST_CASE("gltf mesh: a foreign file's parts are named from its mesh, and its untextured primitives get a default "
          "material",
          "[gltf]") {
  // Two primitives on one vertex set: the first with material 1 (an external
  // texture), the second with one that does not exist (as without one: the
  // rig reader never refused it).
  const Rig rig = test::MakeGridRig(3, 0);
  const fs::path source = test::OutputPath("gltf_mesh_foreign_source.gltf");
  WriteGltf(source, rig);
  nlohmann::json document = nlohmann::json::parse(ReadInputText(source));
  document["meshes"][0]["name"] = "Head";
  document["meshes"][0].erase("extras");
  document["meshes"][0]["primitives"][0]["material"] = 1;
  document["meshes"][0]["primitives"][1]["material"] = 9;
  document["images"] = {{{"uri", "textures/head.png"}}};
  fs::create_directories(source.parent_path() / "textures");
  const std::vector<std::uint8_t> png = test::CheckerPng(4, 2, {255, 0, 0, 255}, {0, 0, 255, 255});
  WriteFileAtomically(source.parent_path() / "textures" / "head.png", std::string(png.begin(), png.end()));
  document["textures"] = {{{"source", 0}}};
  document["materials"] = {{{"name", "unused"}},
                           {{"name", "head"},
                            {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.4, 0.3, 1.0}},
                                                      {"baseColorTexture", {{"index", 0}}}}},
                            {"alphaMode", "BLEND"}}};
  const fs::path path = test::OutputPath("gltf_mesh_foreign.gltf");
  WriteFileAtomically(path, document.dump());

  const Mesh mesh = ReadGltfMesh(path);
  CHECK(mesh.part_names == std::vector<std::string>{"Head.head", "Head.primitive1"});
  REQUIRE(mesh.materials.size() == 3);
  CHECK(mesh.materials[1].name == "head");
  REQUIRE(mesh.materials[1].base_colour_image == 0);
  REQUIRE(mesh.images.size() == 1);
  CHECK(mesh.images[0].name == "head.png");
  CHECK(mesh.images[0].bytes == png);
  CHECK(mesh.materials[1].base_colour.b == Approx(0.3f));
  CHECK(mesh.materials[1].alpha_mode == AlphaMode::kBlend);
  CHECK(mesh.materials[2].name == "default");
  const std::size_t half = mesh.triangle_count() / 2;
  CHECK(mesh.triangle_materials.front() == 1);
  CHECK(mesh.triangle_materials[half] == 2);
  CHECK(mesh.corner_normals.size() == mesh.triangle_count() * 3);
  // The rig reader names parts as the mesh reader does.
  CHECK(ReadGltf(path).parts()[0].name == "Head.head");
}

TEST_CASE("gltf mesh: files with UV seams and materials pass the Khronos validator", "[gltf][gltf-validator]") {
  const Rig rig = test::MakeGridRig(6, 4, true);
  const fs::path path = test::OutputPath("gltf_validate_seams.glb");
  WriteGltf(path, rig, SeamedSurface(rig));  // with embedded PNGs
  test::RequireValidatorAccepts(path);
}

}  // namespace facerig
