// Hostile glTF and GLB files: deep JSON, buffer and image URIs that lead out
// of the file's folder or to FIFOs, data URIs of the wrong length, and names
// that are not UTF-8.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/gltf.h"
#include "gltf_internal.h"
#include "facerig/runtime/rig_builder.h"
#include "support/base64.h"
#include "support/hostile_files.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A grid rig as a .gltf document whose buffer 0 is the file `bin_name` beside
// it (written into `folder`), and the buffer's bytes.
struct ExternalGltf {
  json document;
  std::vector<unsigned char> bin;
};
ExternalGltf MakeExternalGltf(const fs::path& folder) {
  const fs::path source = folder / "source.gltf";
  WriteGltf(source, test::MakeGridRig(4, 2, false));
  ExternalGltf gltf{json::parse(ReadFileText(source)), {}};
  fs::remove(source);
  const std::string uri = gltf.document["buffers"][0]["uri"];
  gltf.bin = test::Base64Decode(uri.substr(uri.find(',') + 1));
  return gltf;
}

void WriteBytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
  WriteFileAtomically(path, std::span(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()));
}

// A .glb of `json_text` and `bin` (padded as GLB requires; no BIN chunk when empty).
std::vector<unsigned char> MakeGlb(std::string json_text, const std::vector<unsigned char>& bin) {
  while (json_text.size() % 4 != 0) json_text += ' ';
  std::string bin_text(bin.begin(), bin.end());
  while (bin_text.size() % 4 != 0) bin_text += '\0';
  std::string glb = "glTF";
  auto put32 = [&glb](std::size_t value) {
    for (int i = 0; i < 4; ++i) glb += static_cast<char>((value >> (8 * i)) & 0xFFu);
  };
  put32(2);
  put32(12 + 8 + json_text.size() + (bin_text.empty() ? 0 : 8 + bin_text.size()));
  put32(json_text.size());
  put32(0x4E4F534A);
  glb += json_text;
  if (!bin_text.empty()) {
    put32(bin_text.size());
    put32(0x004E4942);
    glb += bin_text;
  }
  return {glb.begin(), glb.end()};
}

// The IoError reading `path` throws (on another thread, released if it blocks
// on `fifo`), checked to name the file and to be short.
std::string ReadError(const fs::path& path, const fs::path& fifo = {}) {
  const std::string error = test::ErrorWithoutHanging(fifo.empty() ? path : fifo, [&] { ReadGltf(path); });
  INFO(error);
  CHECK(error.rfind(path.string(), 0) == 0);
  CHECK(error.size() < 400);
  const std::size_t message = error.find(": ", path.string().size());
  return message == std::string::npos ? error : error.substr(message + 2);
}

TEST_CASE("gltf container: an external buffer inside the folder reads", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/inside");
  ExternalGltf gltf = MakeExternalGltf(folder);
  fs::create_directories(folder / "data");
  WriteBytes(folder / "data" / "mesh bin.bin", gltf.bin);
  gltf.document["buffers"][0]["uri"] = "data/mesh%20bin.bin";
  WriteFileAtomically(folder / "scene.gltf", gltf.document.dump());
  CHECK(ReadGltf(folder / "scene.gltf").vertex_count() == 16);
  fs::create_symlink("data/mesh bin.bin", folder / "alias.bin");
  gltf.document["buffers"][0]["uri"] = "alias.bin";
  WriteFileAtomically(folder / "alias.gltf", gltf.document.dump());
  CHECK(ReadGltf(folder / "alias.gltf").vertex_count() == 16);
}

TEST_CASE("gltf container: ParseGltf reads from bytes what ReadGltf reads from the file", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/bytes");
  const Rig rig = test::MakeGridRig(4, 2, false);
  for (const char* name : {"grid.glb", "grid.gltf"}) {
    WriteGltf(folder / name, rig);
    const std::vector<std::byte> bytes = ReadFileBytes(folder / name);
    CHECK(test::RigsEqual(ParseGltf(bytes, folder / name), ReadGltf(folder / name), 0.0f));
  }
  CHECK_THROWS_AS(ParseGltf({}, "empty.glb"), IoError);
}

TEST_CASE("gltf container: JSON nested 15,000 levels deep is refused before parsing", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/deep");
  ExternalGltf gltf = MakeExternalGltf(folder);
  gltf.document["buffers"][0].erase("uri");
  gltf.document["extras"] = "DEEP";
  std::string text = gltf.document.dump();
  const std::string deep = std::string(15000, '[') + std::string(15000, ']');
  text.replace(text.find("\"DEEP\""), 6, deep);

  WriteFileAtomically(folder / "deep.gltf", text);
  const std::string gltf_error = ReadError(folder / "deep.gltf");
  CHECK(gltf_error.find("JSON nested deeper than 64 levels") != std::string::npos);
  WriteBytes(folder / "deep.glb", MakeGlb(text, gltf.bin));
  const std::string glb_error = ReadError(folder / "deep.glb");
  CHECK(glb_error.find("JSON nested deeper than 64 levels") != std::string::npos);
  // The root object is the first level; the offset is the file's (20 bytes of GLB headers first).
  const std::size_t byte = text.find(std::string(65, '['));
  try {
    ReadGltf(folder / "deep.glb");
  } catch (const IoError& e) {
    CHECK(e.offset() == static_cast<std::int64_t>(byte + 63 + 20));
  }
}

TEST_CASE("gltf container: buffer URIs that lead out of the folder are refused", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/escape");
  ExternalGltf gltf = MakeExternalGltf(folder);
  WriteBytes(folder / "outside.bin", gltf.bin);
  fs::create_directories(folder / "scene");
  fs::create_symlink("../outside.bin", folder / "scene" / "link.bin");
  fs::create_symlink("..", folder / "scene" / "up");
  auto error_for = [&](const std::string& uri, bool binary) {
    INFO(uri);
    json document = gltf.document;
    document["buffers"][0]["uri"] = uri;
    const fs::path path = folder / "scene" / (binary ? "scene.glb" : "scene.gltf");
    if (binary) {
      WriteBytes(path, MakeGlb(document.dump(), {}));
    } else {
      WriteFileAtomically(path, document.dump());
    }
    return ReadError(path);
  };
  for (bool binary : {false, true}) {
    CHECK(error_for("../outside.bin", binary) ==
          "buffers[0].uri: '../outside.bin' leads outside the file's folder (through '..')");
    CHECK(error_for("%2E%2E/outside.bin", binary) ==
          "buffers[0].uri: '../outside.bin' leads outside the file's folder (through '..')");
    const std::string absolute = fs::absolute(folder / "outside.bin").string();
    CHECK(error_for(absolute, binary) ==
          "buffers[0].uri: '" + absolute + "' is an absolute path (only paths inside the file's folder are read)");
    CHECK(error_for("link.bin", binary) ==
          "buffers[0].uri: 'link.bin' leads outside the file's folder (through a symbolic link)");
    CHECK(error_for("up/outside.bin", binary) ==
          "buffers[0].uri: 'up/outside.bin' leads outside the file's folder (through a symbolic link)");
    CHECK(error_for("missing.bin", binary) == "buffers[0].uri: 'missing.bin' does not exist");
  }
}

TEST_CASE("gltf container: a FIFO as the file or as a buffer is refused without blocking", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/fifo");
  ExternalGltf gltf = MakeExternalGltf(folder);
  test::MakeFifo(folder / "pipe.bin");
  gltf.document["buffers"][0]["uri"] = "pipe.bin";
  WriteFileAtomically(folder / "scene.gltf", gltf.document.dump());
  CHECK(ReadError(folder / "scene.gltf", folder / "pipe.bin") ==
        "buffers[0].uri: 'pipe.bin' is a FIFO (named pipe), not a regular file");
  fs::create_symlink("/dev/zero", folder / "zero.bin");
  gltf.document["buffers"][0]["uri"] = "zero.bin";
  WriteFileAtomically(folder / "zero.gltf", gltf.document.dump());
  CHECK(ReadError(folder / "zero.gltf") == "buffers[0].uri: 'zero.bin' leads outside the file's folder (through a symbolic link)");

  test::MakeFifo(folder / "pipe.glb");
  CHECK(ReadError(folder / "pipe.glb") == "is a FIFO (named pipe), not a regular file");
  fs::create_symlink("/dev/zero", folder / "zero.glb");
  CHECK(ReadError(folder / "zero.glb") == "is a character device, not a regular file");
}

TEST_CASE("gltf container: image files are opened only inside the file's folder, and only when regular",
          "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/images");
  ExternalGltf gltf = MakeExternalGltf(folder);
  WriteBytes(folder / "mesh.bin", gltf.bin);
  gltf.document["buffers"][0]["uri"] = "mesh.bin";
  test::MakeFifo(folder / "pipe.png");
  for (const char* uri : {"pipe.png", "../outside.png", "/etc/passwd"}) {
    INFO(uri);
    gltf.document["images"] = json::array({{{"uri", uri}}});
    WriteFileAtomically(folder / "scene.gltf", gltf.document.dump());
    const std::string prefix = (folder / "scene.gltf").string() + ": images[0].uri: '" + uri + "' ";
    CHECK(test::ErrorWithoutHanging(folder / "pipe.png", [&] { ReadGltf(folder / "scene.gltf"); })
              .rfind(prefix, 0) == 0);
    std::uint64_t size = 0;
    const std::string error = test::ErrorWithoutHanging(folder / "pipe.png", [&] {
      gltf_internal::ParseModel(folder / "scene.gltf", gltf_internal::Format::kText, &size,
                                gltf_internal::Images::kKeepEncoded);
    });
    CHECK(error.rfind(prefix, 0) == 0);
  }
}

TEST_CASE("gltf container: a data URI of the wrong length gives a short error", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/data_uri");
  ExternalGltf gltf = MakeExternalGltf(folder);
  gltf.document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + std::string(4 << 20, 'A');
  WriteFileAtomically(folder / "scene.gltf", gltf.document.dump());
  CHECK(ReadError(folder / "scene.gltf") ==
        "buffers[0].uri: the data URI is not base64 of exactly byteLength bytes (3145728 bytes of base64 data)");
  // nlohmann::json's parse error quotes the token it read: here 1 MB and an escape sequence.
  WriteFileAtomically(folder / "garbage.gltf", "{\"asset\": \"" + std::string(1 << 20, 'a') + "\x1b[2J\"}");
  const std::string error = ReadError(folder / "garbage.gltf");
  CHECK(error.rfind("tinygltf: [json.exception.parse_error.101] parse error", 0) == 0);
  CHECK(error.find('\x1b') == std::string::npos);
}

TEST_CASE("gltf container: names that are not UTF-8", "[gltf][hostile]") {
  const fs::path folder = test::FreshOutputFolder("gltf_hostile/utf8");
  const Rig bad_shape = test::MakeNamedGridRig({"jawOpen", "smile\xFF\xFE"});
  for (const char* name : {"bad.glb", "bad.gltf"}) {
    try {
      WriteGltf(folder / name, bad_shape);
      FAIL("no error");
    } catch (const IoError& e) {
      CHECK(e.kind() == IoErrorKind::kWriteFailed);
      CHECK(std::string(e.what()) == (folder / name).string() +
                                         ": shape 1's name is not valid UTF-8 (byte 5), which glTF requires: "
                                         "rename it");
    }
    CHECK_FALSE(fs::exists(folder / name));
  }
  // A file name that is not UTF-8 only names the mesh and node: written, with '?'.
  const fs::path odd = folder / "t\xE9te.glb";
  WriteGltf(odd, test::MakeNamedGridRig({"jawOpen"}));
  CHECK(ReadGltf(odd).shape_count() == 1);
  const std::vector<std::byte> bytes = ReadFileBytes(odd);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  CHECK(text.find("\"t?te\"") != std::string::npos);
}

}  // namespace
}  // namespace facerig
