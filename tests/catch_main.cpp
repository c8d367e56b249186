// Catch's main. The tools the tests run in-process keep imported template
// folders in a cache (offline/io/template_cache.h): the tests' output folder,
// not the user's home, unless FACERIG_CACHE_DIR says otherwise.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdlib>

int main(int argc, char* argv[]) {
  setenv("FACERIG_CACHE_DIR", FACERIG_TEST_OUTPUT_DIR "/template_cache", 0);
  return Catch::Session().run(argc, argv);
}
