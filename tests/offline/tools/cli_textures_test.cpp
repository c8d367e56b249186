// A textured face through `facerig convert` and `facerig build`: the image
// reaches every output byte for byte, and every corner keeps the UV it had,
// so each corner shows the same texel as in the artist's file.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "cli_app.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/part_roles.h"
#include "support/command_runner.h"
#include "support/gltf_validator.h"
#include "support/test_meshes.h"
#include "support/textured_assets.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> FileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The rig's face material shows the albedo, byte for byte, and its corners
// carry the source's UVs (triangle t of the rig is triangle t of the source
// grouped by part, as builds and LoadRig order them).
void CheckTextured(const Rig& rig, const Mesh& source, const std::vector<std::uint8_t>& albedo) {
  const auto face = std::find_if(rig.materials().begin(), rig.materials().end(),
                                 [](const Material& m) { return m.name == "M_Face"; });
  REQUIRE(face != rig.materials().end());
  REQUIRE(face->base_colour_image >= 0);
  CHECK(rig.images()[static_cast<std::size_t>(face->base_colour_image)].bytes == albedo);
  REQUIRE(rig.triangle_count() == source.triangle_count());
  REQUIRE(!rig.uvs().empty());
  std::size_t mismatches = 0;
  for (std::size_t t = 0; t < source.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      const glm::vec2 uv = rig.uvs()[rig.triangles()[t][c]];
      if (glm::length(uv - source.corner_uvs[t * 3 + c]) > 1e-6f) ++mismatches;
    }
  }
  CHECK(mismatches == 0);
}

}  // namespace

TEST_CASE("(shared data) facerig convert and build keep a textured ICT face's image, UVs and materials",
          "[shared-data][cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_textures");
  const fs::path obj = test::WriteTexturedIctIdentity(folder / "in");
  const std::vector<std::uint8_t> albedo = FileBytes(folder / "in" / "albedo.png");
  const Mesh source = GroupedByPart(ReadObj(obj));
  REQUIRE(source.images.size() == 1);

  const test::CommandOutcome converted =
      test::RunCommand(cli::RunFacerig, {"convert", obj.string(), (folder / "converted.glb").string()});
  INFO(converted.error_output);
  REQUIRE(converted.exit_code == 0);
  test::RequireValidatorAccepts(folder / "converted.glb");
  CheckTextured(LoadRig(folder / "converted.glb"), source, albedo);

  const test::CommandOutcome built = test::RunCommand(
      cli::RunFacerig, {"build", "--template", test::IctDir().string(), "--target", obj.string(), "-o",
                        (folder / "built.glb").string(), "--frig", (folder / "built.frig").string(), "--obj-dir",
                        (folder / "objs").string()});
  INFO(built.error_output);
  REQUIRE(built.exit_code == 0);
  test::RequireValidatorAccepts(folder / "built.glb");
  CheckTextured(LoadRig(folder / "built.glb"), source, albedo);
  CheckTextured(LoadRig(folder / "built.frig"), source, albedo);
  // ICT's MTL gives its eye layers and lashes an opaque grey: the build gives
  // them their role's blended material, so they never cover the eyes.
  const Rig built_rig = LoadRig(folder / "built.glb");
  for (const Part& part : built_rig.parts()) {
    REQUIRE(part.material >= 0);
    const Material& material = built_rig.materials()[static_cast<std::size_t>(part.material)];
    INFO(part.name << ": " << material.name);
    CHECK(material.name == part.name);
    const bool layer = part.name == "M_EyeOcclusion" || part.name == "M_LacrimalFluid" || part.name == "M_EyeBlend" ||
                       part.name == "M_EyeLashes";
    CHECK((material.alpha_mode == AlphaMode::kBlend) == layer);
    if (part.name != "M_Face") CHECK(!IsPlaceholderMaterial(material));
  }
  // The OBJ folder shares one MTL and the image under its own name.
  CHECK(fs::exists(folder / "objs" / "materials.mtl"));
  const Mesh neutral = ReadObj(folder / "objs" / "neutral.obj");
  REQUIRE(neutral.images.size() == 1);
  CHECK(neutral.images[0].bytes == albedo);
  const Mesh blink = ReadObj(folder / "objs" / "eyeBlink_L.obj");
  REQUIRE(blink.images.size() == 1);
  CHECK(blink.corner_uvs == neutral.corner_uvs);
}

}  // namespace facerig
