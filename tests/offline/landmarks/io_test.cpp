// Hostile landmark files (landmarks_io.cpp): read through ReadInputText, so a
// FIFO, a device or an oversized file is refused without blocking; deep JSON
// is refused before parsing; errors are short and name the file and field.
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "support/hostile_files.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::string ErrorOf(std::string_view text) {
  try {
    ParseLandmarksJson(text, "marks.json");
  } catch (const IoError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("Landmark files: a FIFO, a device and a folder are refused without blocking", "[landmarks][hostile]") {
  const fs::path folder = test::FreshOutputFolder("landmarks_hostile");
  const fs::path fifo = folder / "pipe.json";
  test::MakeFifo(fifo);
  CHECK(test::ErrorWithoutHanging(fifo, [&] { ReadLandmarksJson(fifo); }) ==
        fifo.string() + ": is a FIFO (named pipe), not a regular file");
  const fs::path device = folder / "zero.json";
  fs::create_symlink("/dev/zero", device);
  CHECK(test::ErrorWithoutHanging(device, [&] { ReadLandmarksJson(device); }) ==
        device.string() + ": is a character device, not a regular file");
  CHECK_THROWS_WITH(ReadLandmarksJson(folder), Catch::Contains("is a directory, not a regular file"));
}

TEST_CASE("Landmark files: deep, oversized and malformed JSON give short errors naming the field",
          "[landmarks][hostile]") {
  CHECK(ErrorOf("{\"points\": " + std::string(20000, '[') + "}") ==
        "marks.json (byte 74): JSON nested deeper than 64 levels");
  CHECK(ErrorOf(std::string(kMaxLandmarkFileBytes + 1, ' ')) ==
        "marks.json: " + std::to_string(kMaxLandmarkFileBytes + 1) + " bytes (at most 16777216)");
  // A megabyte-long bad token is quoted short, not echoed.
  const std::string long_token = ErrorOf("{\"points\": [" + std::string(1 << 20, 'x') + "]}");
  CHECK(long_token.find("marks.json: not JSON: ") == 0);
  CHECK(long_token.size() < 400);
  CHECK(ErrorOf(R"({"points": [[0, 1, 2], [1, 2]]})") == "marks.json: points[1]: each point must be [x, y, z]");
  CHECK(ErrorOf(R"({"points": [[0, 1, 2]], "indices": [70]})") ==
        "marks.json: indices: landmark index 70 is outside dlib's 0..67");
  CHECK(ErrorOf(R"({"points": [[0, 1, 2]], "confidence": [2]})") == "marks.json: confidence: must be in [0, 1]");
  CHECK(ErrorOf(R"({"points": [[0, 1e39, 2]]})") == "marks.json: points[0]: a landmark point is not finite");
  CHECK(ErrorOf(R"({"points": [[0, 1, 2]], "indices": ["a"]})") ==
        "marks.json: indices: expected an array of landmark indices 0..67");
  // A float index is refused, not cast (3.6e55 to uint32 was undefined behaviour; found by fuzzing).
  CHECK(ErrorOf(R"({"points": [[0, 1, 2]], "indices": [3.6e55]})") ==
        "marks.json: indices: expected an array of landmark indices 0..67");
}

}  // namespace facerig
