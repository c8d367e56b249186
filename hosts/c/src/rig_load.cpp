// Loading rigs: from a file through runtime_io's readers, or from the bytes
// of a .glb or .frig (told apart by their magic).
#include <cstring>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "boundary.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/rig_file.h"
#include "handles.h"

namespace facerig::capi {
namespace {

std::uint32_t ReadU32(const unsigned char* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

// A GLB from memory has no folder: refuse buffers and images it would read
// from files, before the reader resolves them against the working folder.
void RefuseExternalFiles(std::span<const std::byte> bytes, const std::string& name) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 20 || ReadU32(p + 16) != 0x4E4F534Au) return;  // not a GLB with JSON: the reader says why
  const std::uint32_t json_length = ReadU32(p + 12);
  if (json_length > bytes.size() - 20) return;
  const std::string_view text(reinterpret_cast<const char*>(p + 20), json_length);
  CheckJsonNesting(text, name);
  const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
  if (document.is_discarded() || !document.is_object()) return;
  for (const char* array : {"buffers", "images"}) {
    const auto found = document.find(array);
    if (found == document.end() || !found->is_array()) continue;
    for (std::size_t i = 0; i < found->size(); ++i) {
      const nlohmann::json& item = (*found)[i];
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      if (!item["uri"].get<std::string>().starts_with("data:")) {
        throw IoError(IoErrorKind::kOpenFailed, name,
                      std::string(array) + "[" + std::to_string(i) +
                          "].uri names a file, which a rig loaded from bytes cannot read");
      }
    }
  }
}

Rig ParseRigBytes(std::span<const std::byte> bytes, const std::string& name) {
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "FRIG", 4) == 0) return ParseFrig(bytes, name);
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    RefuseExternalFiles(bytes, name);
    // ParseGltf takes the format from the extension.
    return ParseGltf(bytes, name.ends_with(".glb") ? name : name + ".glb");
  }
  throw IoError(IoErrorKind::kBadMagic, name, "neither a .glb (magic \"glTF\") nor a .frig (magic \"FRIG\")", 0, 0);
}

fr_status Publish(Rig rig, fr_rig** out_rig) {
  auto handle = std::make_unique<fr_rig>();
  handle->data = std::make_shared<const LoadedRig>(std::move(rig));
  *out_rig = handle.release();
  return FR_OK;
}

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_rig_load_file(const char* path, fr_rig** out_rig) {
  return Guard([&] {
    FR_REQUIRE(out_rig, "out_rig");
    *out_rig = nullptr;
    FR_REQUIRE(path, "path");
    return Publish(facerig::LoadRig(path), out_rig);
  });
}

fr_status fr_rig_load_bytes(const void* bytes, size_t size, const char* name, fr_rig** out_rig) {
  return Guard([&] {
    FR_REQUIRE(out_rig, "out_rig");
    *out_rig = nullptr;
    if (bytes == nullptr && size > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "bytes is NULL");
    const std::string label = name ? name : "<memory>";
    if (size == 0) throw facerig::IoError(facerig::IoErrorKind::kEmpty, label, "no bytes");
    return Publish(ParseRigBytes(std::span(static_cast<const std::byte*>(bytes), size), label), out_rig);
  });
}

void fr_rig_release(fr_rig* rig) { delete rig; }

}  // extern "C"
