#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/mtl.h"

namespace facerig {
namespace {

// The longest name written (file systems take 255 bytes; a suffix may follow).
constexpr std::size_t kMaxNameBytes = 100;

// `stem` + `extension`, or with "_2", "_3", ... before the extension, the first
// that `taken` (lower case) does not hold; the chosen name is added to it.
std::string Unique(const std::string& stem, const std::string& extension, std::set<std::string>& taken) {
  std::string name = stem + extension;
  for (int n = 2; taken.contains(LowerAscii(name)); ++n) name = stem + "_" + std::to_string(n) + extension;
  taken.insert(LowerAscii(name));
  return name;
}

bool IsFileNameCharacter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
         c == '_';
}

// The image's name without folders and extension, other characters as '_'.
std::string SafeStem(const std::string& name) {
  std::string stem = name.substr(name.find_last_of("/\\") == std::string::npos ? 0 : name.find_last_of("/\\") + 1);
  const std::size_t dot = stem.find_last_of('.');
  if (dot != std::string::npos) stem.resize(dot);
  for (char& c : stem) {
    if (!IsFileNameCharacter(c)) c = '_';
  }
  stem.erase(0, stem.find_first_not_of('.'));
  if (stem.size() > kMaxNameBytes) stem.resize(kMaxNameBytes);
  return stem;
}

void AppendNumber(std::string& out, float value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

// The inverse of reading's roughness = sqrt(2 / (Ns + 2)), capped at the
// exponent range exporters use.
float SpecularExponent(float roughness) {
  const float r = std::clamp(roughness, 0.0f, 1.0f);
  return r <= 0.0f ? 1000.0f : std::min(2.0f / (r * r) - 2.0f, 1000.0f);
}

bool IsPlainFileName(std::string_view name) {
  return !name.empty() && name != "." && name != ".." && name.find_first_of(std::string_view("/\\\0", 3)) == std::string_view::npos;
}

}  // namespace

std::vector<std::string> MtlMaterialNames(std::span<const Material> materials) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    std::string name = materials[i].name.substr(0, kMaxNameBytes);
    for (char& c : name) {
      if (static_cast<unsigned char>(c) <= ' ' || c == 0x7F || c == '#') c = '_';
    }
    if (name.empty()) name = "material" + std::to_string(i);
    names.push_back(Unique(name, "", taken));
  }
  return names;
}

std::vector<std::string> ImageFileNames(std::span<const EncodedImage> images) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::string stem = SafeStem(images[i].name);
    if (stem.empty()) stem = "image" + std::to_string(i);
    names.push_back(Unique(stem, FileExtension(images[i].format), taken));
  }
  return names;
}

std::string FormatMtl(std::span<const Material> materials, std::span<const std::string> material_names,
                      std::span<const std::string> image_files) {
  std::string out = "# written by facerig\n";
  auto append_value = [&out](const char* keyword, float value) {
    out += keyword;
    out += ' ';
    AppendNumber(out, value);
    out += '\n';
  };
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const Material& material = materials[m];
    out += "\nnewmtl " + material_names[m] + "\nKd";
    for (int i = 0; i < 3; ++i) {
      out += ' ';
      AppendNumber(out, material.base_colour[i]);
    }
    out += '\n';
    append_value("d", material.base_colour.a);
    append_value("Ns", SpecularExponent(material.roughness));
    out += "illum 2\n";
    if (material.base_colour_image >= 0) out += "map_Kd " + image_files[static_cast<std::size_t>(material.base_colour_image)] + "\n";
    if (material.normal_image >= 0) out += "map_Bump " + image_files[static_cast<std::size_t>(material.normal_image)] + "\n";
  }
  return out;
}

MtlReference WriteMtl(const std::filesystem::path& folder, std::string_view mtl_name,
                      std::span<const Material> materials, std::span<const EncodedImage> images) {
  const std::filesystem::path mtl_path = folder / mtl_name;
  if (!IsPlainFileName(mtl_name)) {
    throw IoError(IoErrorKind::kWriteFailed, mtl_path.string(), "the MTL name must be a file name without folders");
  }
  for (const Material& material : materials) {
    for (const std::int32_t image : {material.base_colour_image, material.normal_image}) {
      if (image < -1 || image >= static_cast<std::int64_t>(images.size())) {
        throw IoError(IoErrorKind::kInvalidRig, mtl_path.string(),
                      "material '" + material.name + "' names image " + std::to_string(image) + " of " +
                          std::to_string(images.size()));
      }
    }
  }
  MtlReference reference{.mtl_file = std::string(mtl_name), .material_names = MtlMaterialNames(materials)};
  const std::vector<std::string> image_files = ImageFileNames(images);
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::vector<std::uint8_t>& bytes = images[i].bytes;
    WriteFileAtomically(folder / image_files[i], std::as_bytes(std::span(bytes.data(), bytes.size())));
  }
  WriteFileAtomically(mtl_path, FormatMtl(materials, reference.material_names, image_files));
  return reference;
}

}  // namespace facerig
