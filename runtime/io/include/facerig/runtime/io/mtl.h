// Wavefront MTL material libraries, as OBJ files name them with `mtllib`.
//
// Reading keeps what a face needs of each `newmtl`:
//   Kd r [g b]      base colour. Files store display (sRGB-ish) values; like
//                   Blender's and other glTF-minded importers, the numbers are
//                   taken as glTF's linear base colour unchanged (clamped to [0,1]).
//   d a  / Tr t     alpha = d, or 1 - Tr when the material has no `d`;
//                   alpha < 1 makes the material AlphaMode::kBlend.
//   Ns n            roughness = sqrt(2 / (n + 2)), the Blinn-Phong exponent
//                   to GGX roughness relation (Ns 0 -> 1, Ns 1000 -> 0.045).
//   map_Kd          the base colour image;
//   map_Bump, bump, norm   the normal map (bump is strictly a height map,
//                   but exporters of faces write normal maps there).
// Map options (-bm 1.0, -o u v w, -clamp on, ...) before the file name are
// skipped; the file name is the rest of the line, so it may contain spaces.
// Backslashes in file names are read as '/'. Keywords are matched without
// regard to case. `illum`, Ka, Ks, Ke, Ni and other statements are ignored.
//
// Writing (WriteMtl) is the inverse: Kd, d, Ns, map_Kd, map_Bump. What MTL
// cannot say is lost: kMask becomes d (kBlend when below 1), double_sided and
// alpha_cutoff are not written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/material.h"

namespace facerig {

// The largest MTL file read (a face's library is a few kilobytes).
inline constexpr std::uint64_t kMaxMtlFileBytes = std::uint64_t{16} << 20;

// A map statement: the file name as the MTL wrote it, and where.
struct MtlMap {
  std::string file{};       // empty: no map
  std::string statement{};  // the keyword as written, e.g. "map_Kd"
  std::int64_t line = 0;    // 1-based line of the statement
};

struct MtlMaterial {
  Material material{};  // image indices -1: the maps below name files
  MtlMap base_colour_map{};
  MtlMap normal_map{};
};

// The materials of an MTL file in file order (a name defined twice appears
// twice; OBJ reading uses the first). Throws IoError naming
// `path_for_errors` and the 1-based line: kParse for a Kd, d, Tr, Ns or map
// statement before any `newmtl`, a `newmtl` without a name, a map without a
// file name or a malformed number; kNonFinite for NaN or Inf.
std::vector<MtlMaterial> ParseMtl(std::string_view text, const std::string& path_for_errors);

// A `mtllib` statement's file names: several names separated by spaces, or,
// when the words do not all end in ".mtl", the whole text as one name.
std::vector<std::string> SplitMtllibNames(std::string_view rest_of_line);

// What OBJ files written beside an MTL need to use its materials.
struct MtlReference {
  std::string mtl_file{};                     // the name `mtllib` gives, relative to the OBJ
  std::vector<std::string> material_names{};  // the `newmtl` name of each material
};

// Names for the materials as MTL writes them: no spaces or control
// characters, none empty, all different.
std::vector<std::string> MtlMaterialNames(std::span<const Material> materials);
// File names for the images: only letters, digits, '.', '-' and '_', not
// starting with '.', the extension of the image's format, all different
// (ignoring case, for case-insensitive file systems).
std::vector<std::string> ImageFileNames(std::span<const EncodedImage> images);

// The text of an MTL file for `materials`, whose images are written under
// `image_files` (ImageFileNames).
std::string FormatMtl(std::span<const Material> materials, std::span<const std::string> material_names,
                      std::span<const std::string> image_files);

// Writes `folder`/`mtl_name` and the images (their bytes as they are) into
// `folder` under ImageFileNames, each atomically, and returns what OBJs in
// `folder` reference it by. Throws IoError(kWriteFailed) when `mtl_name` is
// not a plain file name or a file cannot be written, and
// IoError(kInvalidRig) when the materials name images that do not exist.
MtlReference WriteMtl(const std::filesystem::path& folder, std::string_view mtl_name,
                      std::span<const Material> materials, std::span<const EncodedImage> images);

}  // namespace facerig
