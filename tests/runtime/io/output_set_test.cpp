// OutputSet's naming (the sets themselves are tested through the commands
// that write them: tests/offline/tools/cli_build_output_set_test.cpp and
// tests/demo/output_set_test.cpp).
#include "facerig/runtime/io/output_set.h"

#include <catch2/catch.hpp>

namespace facerig {

TEST_CASE("output set: a temporary's final file name", "[output-set-names]") {
  CHECK(FinalFileName(".facerig-tmp-1234-face.glb") == "face.glb");
  CHECK(FinalFileName(".facerig-tmp-1234-old-face.glb") == "old-face.glb");
  CHECK(FinalFileName("face.glb") == "face.glb");
  CHECK(FinalFileName(".facerig-tmp-nodash") == ".facerig-tmp-nodash");
}

}  // namespace facerig
