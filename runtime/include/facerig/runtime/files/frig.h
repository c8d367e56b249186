// The compact runtime rig file (.frig): little-endian; a 32-byte header
// (magic "FRIG", version, section count, CRC-32 of everything after the
// header, file size), a section table, then 16-byte aligned sections. Loads
// with one read of the whole file and one copy per array.
//
// Format, version 1
// -----------------
// Every integer and float is little-endian whatever the host; floats are
// IEEE-754 binary32. Offsets are absolute byte offsets from the file's start.
//
// Header (32 bytes, offset 0):
//   0  char[4] magic         "FRIG"
//   4  u32     version       1 (kFrigVersion)
//   8  u32     section_count entries in the section table
//   12 u32     crc32         CRC-32 (IEEE, as zlib) of bytes [32, file_size)
//   16 u64     file_size     total file size in bytes
//   24 u64     reserved      written as 0, ignored by readers
//
// Section table (offset 32, section_count entries of 32 bytes each):
//   0  u32 tag           FourCC, its first character in the lowest byte
//                        ('META' is the bytes "META")
//   4  u32 element_size  bytes per element (fixed per known tag, see below)
//   8  u64 element_count
//   16 u64 offset        multiple of 16, at or after the end of the table
//   24 u64 byte_size     == element_count * element_size; offset + byte_size <= file_size
// Sections follow the table in table order, each starting at the next
// multiple of 16; padding bytes are 0 and the file ends right after the last
// section. Readers skip sections whose tag they do not know (forward
// compatible within a version); a known tag may appear only once.
//
// Sections (element size in bytes; "required" sections must be present even
// when they hold 0 elements):
//   META  32  1 element, required:
//             u32 vertex_count, u32 triangle_count, u32 shape_count,
//             u32 part_count, u32 shape_entry_count (sparse entries over all
//             shapes), u32 units (Units enum: 0 unknown, 1 mm, 2 cm, 3 m),
//             u32 up_axis (0 +Y, 1 +Z), u32 flags (bit 0: has UVs, bit 1: has
//             normal deltas; other bits must be 0)
//   POSI  12  vertex_count neutral positions, f32 x, y, z; required
//   NORM  12  vertex_count unit neutral normals, f32 x, y, z; required
//   TRIS  12  triangle_count triangles, u32 v0, v1, v2 (< vertex_count); required
//   UV00   8  vertex_count texture coordinates, f32 u, v; present iff flag bit 0
//   PART  16  part_count parts: u32 name_offset, u32 name_length (into STRS),
//             u32 first_triangle, u32 triangle_count; the parts tile the
//             triangles in order; required
//   SHAP  16  shape_count shapes: u32 name_offset, u32 name_length (into STRS),
//             u32 entry_offset, u32 entry_count (into SIDX/SPOS/SNRM); the
//             shapes tile the entries in order; required
//   SIDX   4  shape_entry_count u32 vertex indices, strictly increasing within
//             each shape; required
//   SPOS  12  shape_entry_count position deltas, f32 x, y, z; required
//   SNRM  12  shape_entry_count normal deltas, f32 x, y, z; present iff flag bit 1
//   STRS   1  names (UTF-8, not NUL-terminated): parts, shapes, materials,
//             then images; all names together are no longer than STRS; required
//   MATL  48  materials, present iff the rig has any: u32 name_offset,
//             u32 name_length (into STRS), f32 base colour r, g, b, a (linear),
//             i32 base_colour_image, i32 normal_image (into IMGS; -1 none),
//             u32 alpha_mode (0 opaque, 1 mask, 2 blend), f32 alpha_cutoff,
//             u32 flags (bit 0: double-sided; other bits must be 0),
//             f32 roughness; every float finite
//   PMAT   4  part_count i32 material indices (into MATL; -1 none), written
//             with MATL; a file without it loads with every part at -1
//   IMGS  32  images, present iff the rig has any: u32 name_offset,
//             u32 name_length (into STRS; a plain file name such as
//             "skin.png"), u32 format (0 PNG, 1 JPEG), u32 width, u32 height,
//             u32 byte_length (> 0), u64 data_offset (into IMGB)
//   IMGB   1  the images' encoded bytes, present with IMGS: image i starts at
//             the end of image i - 1 rounded up to a multiple of 8 (image 0 at
//             0), padding 0, and the section ends with the last image
//
// Images are embedded, not referenced by path: a runtime file must work when
// copied alone (into a game's assets, over the network), as a .glb does, and a
// loader then opens no second file. The format, width and height must be
// what the bytes' own header says (checked with ProbeImage); pixels are never
// decoded. Files written before these sections existed load without
// materials, and a rig without materials is written without them, byte for
// byte as before; older readers skip them.
//
// Reading checks, in this order, and throws IoError with the path and the
// byte offset of the offending field: size (kEmpty, kTruncated), magic
// (kBadMagic), version (kUnsupportedVersion), file_size (kTruncated), CRC
// (kChecksumMismatch), section table and counts (kAbsurdCount, kTruncated,
// kParse; all before any array is allocated), indices and ranges
// (kIndexOutOfRange), NaN/Inf (kNonFinite), shape index order (kParse), then
// images, materials and part materials (a name outside STRS or an index out
// of range kIndexOutOfRange; image bytes past IMGB kTruncated; ProbeImage's
// kBadMagic, kTruncated, kAbsurdCount; a bad file name, format, alpha mode,
// flags or data offset, or a header that disagrees with IMGS, kParse; a
// non-finite material value kNonFinite), then RigBuilder::Build (kInvalidRig).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

inline constexpr std::uint32_t kFrigVersion = 1;

// Throws IoError: kEmpty, kTruncated, kBadMagic, kUnsupportedVersion,
// kChecksumMismatch, kAbsurdCount, kParse, kIndexOutOfRange, kNonFinite,
// kInvalidRig, with the byte offset (see the order above). Normals go through
// RigBuilder::Build, which renormalises them (may change them by an ulp or two).
Rig ParseFrig(std::span<const std::byte> bytes, const std::string& path_for_errors);
// One read of the whole file, then ParseFrig. Also kOpenFailed.
Rig ReadFrig(const std::filesystem::path& path);

// Deterministic: the same rig always gives the same bytes. Throws
// IoError(kInvalidRig) for a rig no reader could load (no vertices, e.g. a
// default-constructed or moved-from Rig; a non-finite material value; image
// bytes whose header disagrees with the image's format or size).
std::vector<std::byte> SerializeFrig(const Rig& rig);
// Atomic (temporary file + rename): on any failure the previous file, if any,
// is left as it was. Throws IoError naming the path: kInvalidRig as
// SerializeFrig, kWriteFailed when the file cannot be written.
void WriteFrig(const std::filesystem::path& path, const Rig& rig);

// CRC-32 (IEEE 802.3, as zlib).
std::uint32_t Crc32(std::span<const std::byte> bytes);

}  // namespace facerig
