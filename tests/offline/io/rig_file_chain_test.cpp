// A template folder through every rig format: the folder import is offline's
// (LoadRigOrTemplateFolder), the formats are runtime_io's (LoadRig, SaveRig).
#include <catch2/catch.hpp>

#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "support/test_meshes.h"

namespace fs = std::filesystem;

namespace {

// OBJ folder -> rig -> glTF (.glb and .gltf) -> rig -> .frig -> rig: every step
// keeps topology, parts, names and deltas.
void CheckRoundTripChain(const facerig::Rig& start, const std::string& stem, float tolerance) {
  std::string difference;
  for (const char* gltf_ext : {".glb", ".gltf"}) {
    const fs::path gltf = facerig::test::OutputPath(stem + gltf_ext);
    facerig::SaveRig(gltf, start);
    const facerig::Rig from_gltf = facerig::LoadRig(gltf);
    INFO(gltf.string());
    REQUIRE(facerig::test::RigsEqual(start, from_gltf, tolerance, &difference));

    const fs::path frig = facerig::test::OutputPath(stem + gltf_ext + ".frig");
    facerig::SaveRig(frig, from_gltf);
    const facerig::Rig from_frig = facerig::LoadRig(frig);
    INFO(difference);
    REQUIRE(facerig::test::RigsEqual(start, from_frig, tolerance, &difference));
  }
}

}  // namespace

TEST_CASE("Round trip OBJ -> rig -> glTF -> rig -> .frig -> rig on a grid template", "[rig_file]") {
  const fs::path folder = facerig::test::OutputPath("chain_template");
  fs::remove_all(folder);
  fs::create_directories(folder);
  const facerig::Rig grid = facerig::test::MakeGridRig(6, 0);
  facerig::WriteObj(folder / "neutral.obj", grid);
  std::vector<glm::vec3> moved(grid.positions().begin(), grid.positions().end());
  for (std::size_t v = 0; v < moved.size(); v += 3) moved[v].z += 0.01f * static_cast<float>(v);
  facerig::WriteObj(folder / "bulge.obj", moved, {}, {}, grid.triangles(), grid.parts());

  const facerig::Rig rig = facerig::LoadRigOrTemplateFolder(folder);
  REQUIRE(rig.shape_count() == 1);
  REQUIRE(rig.shape(0).vertex_indices.size() == 11);  // every third vertex but vertex 0 (delta 0)
  CheckRoundTripChain(rig, "chain_grid", 0.0f);

  // The neutral alone through .obj.
  const fs::path obj = facerig::test::OutputPath("chain_grid_neutral.obj");
  facerig::SaveRig(obj, rig);
  const facerig::Rig neutral = facerig::LoadRig(obj);
  REQUIRE(neutral.shape_count() == 0);
  REQUIRE(neutral.vertex_count() == rig.vertex_count());
  REQUIRE(neutral.parts().size() == rig.parts().size());
}

TEST_CASE("Round trip of the ICT rig through glTF and .frig (shared data)", "[rig_file][shared-data]") {
  CheckRoundTripChain(facerig::test::IctRig(), "chain_ict", 0.0f);
}
