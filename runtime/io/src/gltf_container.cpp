// The glTF container: which format a path names, parsing a .glb or .gltf
// (with the GLB header checked first, for precise errors), and serialising a
// model atomically.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "gltf_internal.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig::gltf_internal {
namespace {

constexpr std::uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbBinChunk = 0x004E4942;   // "BIN\0"
constexpr std::size_t kGlbHeaderSize = 12;
constexpr std::size_t kGlbChunkHeaderSize = 8;


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

// tinygltf reads external buffers and images only through these callbacks,
// which resolve every URI inside the glTF file's folder and read it as a
// regular file of bounded size. tinygltf is given an empty base folder, so
// that the callbacks see each (percent-decoded) URI as the file names it; it
// then retries "./" + URI, which resolves the same way.
struct ExternalFiles {
  std::filesystem::path gltf_path;
  const tinygltf::Model* model = nullptr;  // being filled by tinygltf
  Images images = Images::kSkip;
  std::optional<IoError> error;  // the first refusal, reported instead of tinygltf's message

  // tinygltf parses buffers before bufferViews, accessors, meshes, nodes,
  // scenes and materials, and images after all of them.
  bool ParsingImages() const {
    const tinygltf::Model& m = *model;
    return !m.bufferViews.empty() || !m.accessors.empty() || !m.meshes.empty() || !m.nodes.empty() ||
           !m.scenes.empty() || !m.materials.empty() || !m.images.empty();
  }
  std::string Field() const {
    return ParsingImages() ? "images[" + std::to_string(model->images.size()) + "].uri"
                           : "buffers[" + std::to_string(model->buffers.size()) + "].uri";
  }
  void Refuse(const IoError& refusal) {
    if (!error) error = refusal;
  }
  // The URI as the file names it, without the "./" of tinygltf's retry.
  static std::string_view Uri(const std::string& name) {
    std::string_view uri(name);
    if (uri.starts_with("./")) uri.remove_prefix(2);
    return uri;
  }
};

bool ExternalFileExists(const std::string& name, void* user_data) {
  auto& files = *static_cast<ExternalFiles*>(user_data);
  // A rig needs no texture: image files are not even opened.
  if (files.images == Images::kSkip && files.ParsingImages()) return false;
  const std::string field = files.Field();
  try {
    const std::filesystem::path resolved = ResolveInsideFolder(files.gltf_path, ExternalFiles::Uri(name), field);
    struct stat status {};
    if (::stat(resolved.c_str(), &status) == 0) return true;
    // A missing image stays a uri, as before; a missing buffer is an error.
    if (!files.ParsingImages()) {
      files.Refuse(IoError(IoErrorKind::kOpenFailed, files.gltf_path.string(),
                           field + ": '" + QuoteInput(ExternalFiles::Uri(name)) + "' does not exist"));
    }
  } catch (const IoError& refusal) {
    files.Refuse(refusal);
  }
  return false;
}

bool ReadExternalFile(std::vector<unsigned char>* out, std::string* error, const std::string& name,
                      void* user_data) {
  auto& files = *static_cast<ExternalFiles*>(user_data);
  const std::string field = files.Field();
  try {
    const std::filesystem::path resolved = ResolveInsideFolder(files.gltf_path, ExternalFiles::Uri(name), field);
    std::vector<std::byte> bytes;
    try {
      bytes = ReadInputFile(resolved);
    } catch (const IoError& e) {
      throw IoError(e.kind(), files.gltf_path.string(),
                    field + ": '" + QuoteInput(ExternalFiles::Uri(name)) + "' " + e.message());
    }
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    out->assign(data, data + bytes.size());
    return true;
  } catch (const IoError& refusal) {
    files.Refuse(refusal);
    *error = refusal.message();
    return false;
  }
}

// tinygltf's default expands "~" and environment variables (wordexp): not here.
std::string KeepFilePath(const std::string& path, void*) { return path; }

bool WriteNoFile(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
  *error = "facerig writes no files through tinygltf";
  return false;
}

// tinygltf's error, short enough for a terminal: a data URI that does not
// decode to its buffer's byteLength is named, not echoed (tinygltf quotes
// the whole URI), and anything else is cut to a couple of lines.
std::string ShortTinygltfError(std::string error, const tinygltf::Model& model) {
  while (!error.empty() && std::isspace(static_cast<unsigned char>(error.back()))) error.pop_back();
  if (error.empty()) return "cannot parse";
  static constexpr std::string_view kDecodeFailed = "Failed to decode 'uri' : ";
  if (const std::size_t at = error.find(kDecodeFailed); at != std::string::npos) {
    const std::size_t data = error.find(',', at);
    const std::size_t end = error.find(" in Buffer", at);
    std::string detail;
    if (data != std::string::npos && end != std::string::npos && data < end) {
      detail = " (" + std::to_string((end - data - 1) / 4 * 3) + " bytes of base64 data)";
    }
    return "buffers[" + std::to_string(model.buffers.size()) +
           "].uri: the data URI is not base64 of exactly byteLength bytes" + detail;
  }
  for (std::size_t i = 0; i < error.size(); ++i) {
    if (error[i] == '\n') error.replace(i, 1, "; ");
  }
  return "tinygltf: " + QuoteInput(error);
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

// Length of the valid UTF-8 sequence at the start of `text`, 0 when invalid
// (overlong forms, surrogates and code points past U+10FFFF included, as
// nlohmann::json refuses them when tinygltf serialises).
std::size_t Utf8SequenceLength(std::string_view text) {
  const auto byte = [&text](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (text.size() < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i) {
    if (byte(i) < 0x80 || byte(i) > 0xBF) return 0;
  }
  return length;
}

// Byte offset of the first byte that is not valid UTF-8, or npos.
std::size_t FirstInvalidUtf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = Utf8SequenceLength(text.substr(i));
    if (length == 0) return i;
    i += length;
  }
  return std::string_view::npos;
}

// Checks what tinygltf would take badly: the GLB container (for precise
// errors) or the start of the JSON, and the JSON's nesting. A .gltf that is
// really binary is read as such (`format` becomes kBinary); the converse is a
// wrong magic. Returns the bytes to parse.
std::span<const unsigned char> CheckContainer(std::span<const unsigned char> bytes, const std::string& where,
                                              Format* format) {
  if (bytes.empty()) throw IoError(IoErrorKind::kEmpty, where, "the file is empty");
  if (*format == Format::kText && bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    *format = Format::kBinary;
  }
  if (*format == Format::kBinary) {
    bytes = bytes.first(CheckGlbHeader(bytes, where));
    const std::size_t json_length = LoadU32(bytes.data() + kGlbHeaderSize);
    const auto* json = reinterpret_cast<const char*>(bytes.data() + kGlbHeaderSize + kGlbChunkHeaderSize);
    try {
      CheckJsonNesting(std::string_view(json, json_length), where);
    } catch (const IoError& e) {  // the offset in the file, not in the chunk
      throw IoError(e.kind(), where, e.message(), 0,
                    e.offset() + static_cast<std::int64_t>(kGlbHeaderSize + kGlbChunkHeaderSize));
    }
  } else {
    std::size_t first = 0;
    if (bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) first = 3;
    while (first < bytes.size() && std::isspace(bytes[first])) ++first;
    if (first == bytes.size() || bytes[first] != '{') {
      throw IoError(IoErrorKind::kBadMagic, where, "not glTF JSON (it does not start with '{')", 0,
                    static_cast<std::int64_t>(first));
    }
    CheckJsonNesting(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), where);
  }
  return bytes;
}

}  // namespace

void RequireUtf8Names(const Rig& rig, const std::string& path) {
  auto check = [&path](std::string_view name, const char* what, std::size_t index) {
    const std::size_t bad = FirstInvalidUtf8(name);
    if (bad == std::string_view::npos) return;
    throw IoError(IoErrorKind::kWriteFailed, path,
                  std::string(what) + " " + std::to_string(index) + "'s name is not valid UTF-8 (byte " +
                      std::to_string(bad) + "), which glTF requires: rename it");
  };
  for (std::size_t s = 0; s < rig.shape_count(); ++s) check(rig.shape_name(s), "shape", s);
  for (std::size_t p = 0; p < rig.parts().size(); ++p) check(rig.parts()[p].name, "part", p);
}

std::string SanitizedUtf8(std::string_view text) {
  std::string result;
  result.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = Utf8SequenceLength(text.substr(i));
    result.append(length == 0 ? std::string_view("?") : text.substr(i, length));
    i += std::max<std::size_t>(length, 1);
  }
  return result;
}

Format FormatFromExtension(const std::filesystem::path& path) {
  const std::string extension = LowerExtension(path);
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
  // tinygltf takes 32-bit lengths; GLB cannot exceed 4 GiB anyway.
  const std::vector<std::byte> file = ReadInputFile(path, std::numeric_limits<std::uint32_t>::max());
  *file_size = file.size();
  return ParseModelBytes({reinterpret_cast<const unsigned char*>(file.data()), file.size()}, path, format, images);
}

tinygltf::Model ParseModelBytes(std::span<const unsigned char> bytes, const std::filesystem::path& path,
                                Format format, Images images) {
  const std::string where = path.string();
  bytes = CheckContainer(bytes, where, &format);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(images == Images::kSkip ? &SkipImage : &KeepEncodedImage, nullptr);
  tinygltf::Model model;
  ExternalFiles files{path, &model, images, std::nullopt};
  loader.SetFsCallbacks({&ExternalFileExists, &KeepFilePath, &ReadExternalFile, &WriteNoFile, &files});
  std::string error, warning;
  const std::string base_dir;  // see ExternalFiles
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
  if (files.error) throw *files.error;
  if (!loaded) throw IoError(IoErrorKind::kParse, where, ShortTinygltfError(std::move(error), model));
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
  bool written = false;
  try {
    written = writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!binary, binary) && stream;
  } catch (const std::exception& e) {
    // nlohmann::json throws on a string that is not valid UTF-8.
    throw IoError(IoErrorKind::kWriteFailed, path.string(),
                  "tinygltf could not serialise the model: " + QuoteInput(e.what()));
  }
  if (!written) throw IoError(IoErrorKind::kWriteFailed, path.string(), "tinygltf could not serialise the model");
  WriteFileAtomically(path, std::move(stream).str());  // no copy where str() && exists (C++20)
}

}  // namespace facerig::gltf_internal
