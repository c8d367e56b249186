// The glTF container: which format a path names, parsing a .glb or .gltf
// (with the GLB header checked first, for precise errors), and serialising a
// model atomically.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/atomic_file.h"
#include "facerig/runtime/io/gltf_internal.h"

namespace facerig::gltf_internal {
namespace {

constexpr std::uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbBinChunk = 0x004E4942;   // "BIN\0"
constexpr std::size_t kGlbHeaderSize = 12;
constexpr std::size_t kGlbChunkHeaderSize = 8;

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Images are never needed for a rig; this keeps tinygltf from decoding any.
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
               void*) {
  return true;
}

// tinygltf keeps neither the bytes nor the uri of a data-URI image, and
// re-encoding decoded pixels would change the artist's file: keep the bytes
// as they are. (Images in bufferViews already stay where they are.)
bool KeepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0) image->image.assign(bytes, bytes + size);
  return true;
}

std::uint32_t LoadU32(const unsigned char* p) {
  // GLB is little-endian, as is every platform facerig builds on.
  std::uint32_t value;
  std::memcpy(&value, p, sizeof(value));
  return value;
}

// Checks the GLB container before tinygltf sees it, so that truncation and a
// wrong magic get their own error kinds (tinygltf reports both as "invalid").
// Returns the declared length (bytes after it are ignored).
std::size_t CheckGlbHeader(std::span<const unsigned char> bytes, const std::string& path) {
  static constexpr unsigned char kMagic[4] = {'g', 'l', 'T', 'F'};
  const std::size_t size = bytes.size();
  if (std::memcmp(bytes.data(), kMagic, std::min<std::size_t>(size, 4)) != 0) {
    throw IoError(IoErrorKind::kBadMagic, path, "not a binary glTF (no 'glTF' magic)", 0, 0);
  }
  if (size < kGlbHeaderSize + kGlbChunkHeaderSize) {
    throw IoError(IoErrorKind::kTruncated, path,
                  "the file ends inside the GLB header (" + std::to_string(size) + " bytes)", 0,
                  static_cast<std::int64_t>(size));
  }
  const std::uint32_t version = LoadU32(bytes.data() + 4);
  if (version != 2) {
    throw IoError(IoErrorKind::kUnsupportedVersion, path,
                  "GLB version " + std::to_string(version) + " (only 2 is supported)", 0, 4);
  }
  const std::uint32_t length = LoadU32(bytes.data() + 8);
  if (length > size) {
    throw IoError(IoErrorKind::kTruncated, path,
                  "the GLB header declares " + std::to_string(length) + " bytes but the file has " +
                      std::to_string(size),
                  0, static_cast<std::int64_t>(size));
  }
  const std::uint64_t json_length = LoadU32(bytes.data() + 12);
  const std::uint64_t json_end = kGlbHeaderSize + kGlbChunkHeaderSize + json_length;
  if (json_end > length) {
    throw IoError(IoErrorKind::kTruncated, path,
                  "the JSON chunk (" + std::to_string(json_length) + " bytes) runs past the end of the data",
                  0, 12);
  }
  if (LoadU32(bytes.data() + 16) != kGlbJsonChunk) {
    throw IoError(IoErrorKind::kParse, path, "the first GLB chunk is not JSON", 0, 16);
  }
  if (json_end < length) {
    if (json_end + kGlbChunkHeaderSize > length) {
      throw IoError(IoErrorKind::kTruncated, path, "the file ends inside the BIN chunk header", 0,
                    static_cast<std::int64_t>(json_end));
    }
    const std::uint64_t bin_length = LoadU32(bytes.data() + json_end);
    if (json_end + kGlbChunkHeaderSize + bin_length > length) {
      throw IoError(IoErrorKind::kTruncated, path,
                    "the BIN chunk (" + std::to_string(bin_length) + " bytes) runs past the end of the data",
                    0, static_cast<std::int64_t>(json_end));
    }
    if (LoadU32(bytes.data() + json_end + 4) != kGlbBinChunk) {
      throw IoError(IoErrorKind::kParse, path, "the second GLB chunk is not BIN", 0,
                    static_cast<std::int64_t>(json_end + 4));
    }
  }
  return length;
}

}  // namespace

Format FormatFromExtension(const std::filesystem::path& path) {
  const std::string extension = Lowercase(path.extension().string());
  if (extension == ".glb") return Format::kBinary;
  if (extension == ".gltf") return Format::kText;
  throw IoError(IoErrorKind::kUnsupportedFormat, path.string(),
                "expected a .glb or .gltf extension, got '" + path.extension().string() + "'");
}

void RefuseCompression(const tinygltf::Model& model, const std::string& path) {
  for (const char* extension : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    auto uses = [extension](const std::vector<std::string>& names) {
      return std::find(names.begin(), names.end(), extension) != names.end();
    };
    if (uses(model.extensionsUsed) || uses(model.extensionsRequired)) {
      throw IoError(IoErrorKind::kUnsupportedFormat, path,
                    std::string("the file uses ") + extension +
                        ": facerig reads and writes uncompressed meshes only (export it uncompressed)");
    }
  }
}

tinygltf::Model ParseModel(const std::filesystem::path& path, Format format, std::uint64_t* file_size,
                           Images images) {
  const std::string where = path.string();
  // tinygltf takes 32-bit lengths; GLB cannot exceed 4 GiB anyway.
  const std::vector<std::byte> file = ReadFileBytes(path, std::numeric_limits<std::uint32_t>::max());
  if (file.empty()) throw IoError(IoErrorKind::kEmpty, where, "the file is empty");
  *file_size = file.size();
  std::span<const unsigned char> bytes(reinterpret_cast<const unsigned char*>(file.data()), file.size());

  // A .gltf that is really binary is read as such; the converse is a wrong magic.
  if (format == Format::kText && bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    format = Format::kBinary;
  }
  if (format == Format::kBinary) {
    bytes = bytes.first(CheckGlbHeader(bytes, where));
  } else {
    std::size_t first = 0;
    if (bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) first = 3;
    while (first < bytes.size() && std::isspace(bytes[first])) ++first;
    if (first == bytes.size() || bytes[first] != '{') {
      throw IoError(IoErrorKind::kBadMagic, where, "not glTF JSON (it does not start with '{')", 0,
                    static_cast<std::int64_t>(first));
    }
  }

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(images == Images::kSkip ? &SkipImage : &KeepEncodedImage, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const std::string base_dir = path.parent_path().string();
  bool loaded = false;
  try {
    const auto size = static_cast<unsigned int>(bytes.size());
    if (format == Format::kBinary) {
      loaded = loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), size, base_dir);
    } else {
      loaded = loader.LoadASCIIFromString(&model, &error, &warning,
                                          reinterpret_cast<const char*>(bytes.data()), size, base_dir);
    }
  } catch (const std::exception& e) {
    // tinygltf throws on a few malformed inputs (e.g. a zero-length GLB buffer).
    error = e.what();
    loaded = false;
  }
  if (!loaded) {
    while (!error.empty() && std::isspace(static_cast<unsigned char>(error.back()))) error.pop_back();
    throw IoError(IoErrorKind::kParse, where, "tinygltf: " + (error.empty() ? "cannot parse" : error));
  }
  return model;
}

void WriteModel(const std::filesystem::path& path, Format format, const tinygltf::Model& model) {
  // GLB stores 32-bit lengths; base64 text grows by 4/3.
  std::size_t buffer_size = 0;
  for (const tinygltf::Buffer& buffer : model.buffers) buffer_size += buffer.data.size();
  if (buffer_size > std::numeric_limits<std::uint32_t>::max() / 2) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(),
                  "the data (" + std::to_string(buffer_size) + " bytes) is too large for glTF");
  }
  tinygltf::TinyGLTF writer;
  // Images are written as they are (uri or bufferView), never re-encoded or
  // written as files beside the output.
  writer.SetImageWriter(nullptr, nullptr);
  std::ostringstream stream;
  const bool binary = format == Format::kBinary;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!binary, binary) || !stream) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "tinygltf could not serialise the model");
  }
  WriteFileAtomically(path, stream.view());
}

}  // namespace facerig::gltf_internal
