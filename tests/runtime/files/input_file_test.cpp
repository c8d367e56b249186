#include "facerig/runtime/files/input_file.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/shape_mapping_files.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "support/command_runner.h"
#include "support/hostile_files.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// The IoError that `read` throws; fails the test when it throws none.
IoError ErrorOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const IoError& e) {
    return e;
  }
  FAIL("no IoError");
  throw;  // unreachable
}

using test::Contains;

std::string Nested(int depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// Every reader in facerig, by the extension it reads.
const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>>& AllReaders() {
  static const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>> readers = {
      {".frig", [](const fs::path& p) { ReadFrig(p); }},
      {".obj", [](const fs::path& p) { ReadObj(p); }},
      {".glb", [](const fs::path& p) { ReadGltf(p); }},
      {".gltf", [](const fs::path& p) { ReadGltf(p); }},
      {".track.json", [](const fs::path& p) { ReadPhonemeTrack(p); }},
      {".visemes.json", [](const fs::path& p) { ReadVisemeMappingFile(p); }},
      {".emotions.json", [](const fs::path& p) { ReadEmotionFile(p); }},
  };
  return readers;
}

TEST_CASE("io: input file reads regular files, also through a symbolic link", "[io][input-file]") {
  const fs::path folder = test::FreshOutputFolder("input_file/regular");
  WriteFileAtomically(folder / "a.txt", std::string_view("hello"));
  CHECK(ReadInputText(folder / "a.txt") == "hello");
  CHECK(ReadInputFile(folder / "a.txt").size() == 5);
  fs::create_symlink("a.txt", folder / "link.txt");
  CHECK(ReadInputText(folder / "link.txt") == "hello");
  WriteFileAtomically(folder / "empty.txt", std::string_view());
  CHECK(ReadInputText(folder / "empty.txt").empty());
}

TEST_CASE("io: input file refuses a directory, a FIFO, a device and a missing file", "[io][input-file]") {
  const fs::path folder = test::FreshOutputFolder("input_file/not_regular");
  IoError directory = ErrorOf([&] { ReadInputFile(folder); });
  CHECK(directory.kind() == IoErrorKind::kOpenFailed);
  CHECK(Contains(directory.what(), "is a directory, not a regular file"));

  const fs::path fifo = folder / "pipe";
  test::MakeFifo(fifo);
  const std::string fifo_error = test::ErrorWithoutHanging(fifo, [&] { ReadInputFile(fifo); });
  CHECK(fifo_error == fifo.string() + ": is a FIFO (named pipe), not a regular file");

  IoError zero = ErrorOf([] { ReadInputFile("/dev/zero"); });
  CHECK(zero.kind() == IoErrorKind::kOpenFailed);
  CHECK(std::string(zero.what()) == "/dev/zero: is a character device, not a regular file");

  IoError missing = ErrorOf([&] { ReadInputFile(folder / "missing"); });
  CHECK(missing.kind() == IoErrorKind::kOpenFailed);
  CHECK(missing.path() == (folder / "missing").string());
}

TEST_CASE("io: input file checks the size cap before reading", "[io][input-file]") {
  const fs::path path = test::OutputPath("input_file_cap.txt");
  WriteFileAtomically(path, std::string(1000, 'x'));
  CHECK(ReadInputText(path, 1000).size() == 1000);
  IoError error = ErrorOf([&] { ReadInputText(path, 999); });
  CHECK(error.kind() == IoErrorKind::kAbsurdCount);
  CHECK(error.message() == "file of 1000 bytes is larger than the limit of 999");
}

TEST_CASE("io: paths named in a file resolve only inside its folder", "[io][input-file]") {
  const fs::path folder = test::FreshOutputFolder("input_file/confined");
  fs::create_directories(folder / "scene" / "textures");
  WriteFileAtomically(folder / "outside.bin", std::string_view("secret"));
  WriteFileAtomically(folder / "scene" / "inside.bin", std::string_view("data"));
  const fs::path file = folder / "scene" / "scene.gltf";
  const fs::path scene = fs::canonical(folder / "scene");

  CHECK(ResolveInsideFolder(file, "inside.bin", "buffers[0].uri") == scene / "inside.bin");
  CHECK(ResolveInsideFolder(file, "textures/../inside.bin", "f") == scene / "inside.bin");
  CHECK(ResolveInsideFolder(file, "textures/new.png", "f") == scene / "textures" / "new.png");
  fs::create_symlink("inside.bin", folder / "scene" / "alias.bin");
  CHECK(ResolveInsideFolder(file, "alias.bin", "f") == scene / "inside.bin");

  auto refused = [&file](std::string_view reference) {
    IoError error = ErrorOf([&] { ResolveInsideFolder(file, reference, "buffers[2].uri"); });
    CHECK(error.kind() == IoErrorKind::kOpenFailed);
    CHECK(error.path() == file.string());
    return error.message();
  };
  CHECK(refused("../outside.bin") ==
        "buffers[2].uri: '../outside.bin' leads outside the file's folder (through '..')");
  CHECK(refused("textures/../../outside.bin") ==
        "buffers[2].uri: 'textures/../../outside.bin' leads outside the file's folder (through '..')");
  CHECK(refused("/etc/passwd") ==
        "buffers[2].uri: '/etc/passwd' is an absolute path (only paths inside the file's folder are read)");
  CHECK(refused("") == "buffers[2].uri: '' is empty");
  CHECK(refused(std::string_view("a\0b", 3)) == "buffers[2].uri: 'a?b' contains a NUL byte");
  fs::create_symlink("../outside.bin", folder / "scene" / "escape.bin");
  fs::create_symlink("..", folder / "scene" / "up");
  CHECK(refused("escape.bin") ==
        "buffers[2].uri: 'escape.bin' leads outside the file's folder (through a symbolic link)");
  CHECK(refused("up/outside.bin") ==
        "buffers[2].uri: 'up/outside.bin' leads outside the file's folder (through a symbolic link)");
  CHECK(refused(std::string(5000, 'a') + "/../../x").size() < 400);
}

TEST_CASE("io: JSON nesting is bounded before parsing", "[io][input-file]") {
  CHECK_NOTHROW(CheckJsonNesting(Nested(kMaxJsonNesting), "a.json"));
  CHECK_NOTHROW(CheckJsonNesting("{\"a\": \"" + std::string(1000, '[') + "\"}", "a.json"));
  CHECK_NOTHROW(CheckJsonNesting("[\"\\\"[[[[\"]", "a.json", 1));
  IoError deep = ErrorOf([] { CheckJsonNesting(Nested(15000), "deep.json"); });
  CHECK(deep.kind() == IoErrorKind::kParse);
  CHECK(std::string(deep.what()) == "deep.json (byte 64): JSON nested deeper than 64 levels");
  IoError objects = ErrorOf([] { CheckJsonNesting("{\"a\":{\"b\":[{}]}}", "o.json", 3); });
  CHECK(objects.offset() == 11);
}

TEST_CASE("io: quoted input is short and printable", "[io][input-file]") {
  CHECK(QuoteInput("abc") == "abc");
  CHECK(QuoteInput("a\nb\x1b[31m\xff") == "a?b?[31m?");
  CHECK(QuoteInput(std::string(1 << 20, 'x')) == std::string(kMaxQuotedInputBytes, 'x') + "...");
}

TEST_CASE("io: every reader refuses a FIFO and a device without blocking", "[io][input-file]") {
  const fs::path folder = test::FreshOutputFolder("input_file/readers");
  for (const auto& [extension, read] : AllReaders()) {
    INFO(extension);
    const fs::path fifo = folder / ("pipe" + extension);
    test::MakeFifo(fifo);
    const std::string error = test::ErrorWithoutHanging(fifo, [&] { read(fifo); });
    CHECK(error == fifo.string() + ": is a FIFO (named pipe), not a regular file");
    const fs::path device = folder / ("zero" + extension);
    fs::create_symlink("/dev/zero", device);
    const std::string device_error = test::ErrorWithoutHanging(device, [&] { read(device); });
    CHECK(device_error == device.string() + ": is a character device, not a regular file");
  }
}

TEST_CASE("io: JSON readers refuse deep nesting", "[io][input-file]") {
  const fs::path folder = test::FreshOutputFolder("input_file/deep_json");
  const std::string deep = "{\"version\": 1, \"extras\": " + Nested(15000) + "}";
  for (const auto& [extension, read] : AllReaders()) {
    if (!Contains(extension, ".json")) continue;
    INFO(extension);
    const fs::path path = folder / ("deep" + extension);
    WriteFileAtomically(path, deep);
    IoError error = ErrorOf([&] { read(path); });
    CHECK(error.kind() == IoErrorKind::kParse);
    CHECK(std::string(error.what()) == path.string() + " (byte 88): JSON nested deeper than 64 levels");
  }
}

}  // namespace
}  // namespace facerig
