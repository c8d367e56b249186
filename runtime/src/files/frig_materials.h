// The material sections of .frig v1 ('MATL', 'PMAT', 'IMGS', 'IMGB'; frig.h
// documents them): read and written apart from the mesh sections, which the
// reader and the writer handle in frig_read.cpp and frig_write.cpp.
// Private to facerig::runtime.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/material.h"
#include "facerig/runtime/rig.h"
#include "files/frig_format.h"

namespace facerig::frig_format {

// --- Reading -----------------------------------------------------------------

// The section counts that the material sections must agree on: 'PMAT' holds
// one entry per part, 'IMGS' and 'IMGB' come together, and material and image
// counts fit the i32 indices that name them. Throws IoError (kAbsurdCount,
// kParse) naming `path`; allocates nothing.
void CheckMaterialCounts(const SectionRefs& sections, std::uint32_t part_count, const std::string& path);

struct FrigMaterials {
  std::vector<Material> materials;
  std::vector<EncodedImage> images;
  std::vector<std::int32_t> part_materials;  // one per part; all -1 when the file has no 'PMAT'
};

// Every field checked (names, enums, finite floats, indices, image bytes
// probed against their declared format and size). `name_bytes` is the length
// of the names read before (parts and shapes): all names together must fit in
// 'STRS'. Throws IoError naming `path` with the offending field's offset.
FrigMaterials ReadFrigMaterials(std::span<const std::byte> file, const SectionRefs& sections,
                                std::uint32_t part_count, std::uint64_t name_bytes, const std::string& path);

// --- Writing -----------------------------------------------------------------

// Element counts of the four sections for `rig`; a section is present only
// when the rig has something to put in it, so a rig without materials gives
// the bytes an older facerig wrote.
void PlanMaterialSections(const Rig& rig, std::array<std::uint64_t, kSectionKindCount>& counts,
                          std::array<bool, kSectionKindCount>& present);

// Throws IoError(kInvalidRig) naming `path` for materials or images that the
// reader would refuse (a non-finite value, image bytes whose header does not
// match the image's format and size, an image over 4 GiB).
void CheckMaterialsWritable(const Rig& rig, const std::string& path);

// Names are (offset, length) in 'STRS', one per material and per image.
void WriteMaterialSections(const Rig& rig, std::span<const NameRef> material_names,
                           std::span<const NameRef> image_names,
                           const std::array<std::uint64_t, kSectionKindCount>& offsets, std::byte* file);

}  // namespace facerig::frig_format
