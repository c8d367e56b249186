#include "support/gltf_validator.h"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

namespace facerig::test {

void RequireValidatorAccepts(const std::filesystem::path& path) {
#if defined(FACERIG_GLTF_VALIDATOR) && defined(FACERIG_NODE)
  const std::filesystem::path report = std::filesystem::path(path).concat(".validation.txt");
  const std::string command = std::string("\"") + FACERIG_NODE + "\" \"" + FACERIG_GLTF_VALIDATOR + "\" \"" +
                              path.string() + "\" > \"" + report.string() + "\" 2>&1";
  const int status = std::system(command.c_str());
  const int exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ostringstream text;
  text << std::ifstream(report).rdbuf();
  INFO(command);
  INFO(text.str());
  REQUIRE(exit_code == 0);
#else
  (void)path;
  FAIL(
      "the Khronos glTF validator is not set up: run\n"
      "  npm ci --prefix tests/runtime/io/gltf_validator\n"
      "in the source folder (needs node and npm), then re-run cmake so that it finds\n"
      "tests/runtime/io/gltf_validator/node_modules");
#endif
}

}  // namespace facerig::test
