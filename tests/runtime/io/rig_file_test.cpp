#include "facerig/runtime/io/rig_file.h"

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "support/test_meshes.h"

TEST_CASE("Rig files: unknown extensions are refused by name", "[rig_file][malformed]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(3, 1);
  try {
    facerig::SaveRig(facerig::test::OutputPath("rig.fbx"), rig);
    FAIL("no error");
  } catch (const facerig::IoError& error) {
    REQUIRE(error.kind() == facerig::IoErrorKind::kUnsupportedFormat);
    REQUIRE(std::string(error.what()).find("rig.fbx") != std::string::npos);
  }
  REQUIRE_THROWS_AS(facerig::LoadRig(facerig::test::OutputPath("rig.fbx")), facerig::IoError);
}
