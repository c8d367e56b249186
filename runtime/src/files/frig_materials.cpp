// The material sections of .frig v1: materials, the material of each part,
// and the images embedded in the file.
#include "files/frig_materials.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/image_file.h"

namespace facerig::frig_format {
namespace {

constexpr std::uint64_t kMaxIndexedCount = std::numeric_limits<std::int32_t>::max();

// Where each image's bytes start in 'IMGB' (8-aligned, in order) and the
// section's size: the end of the last image.
struct ImageData {
  std::vector<std::uint64_t> offsets;
  std::uint64_t size = 0;
};

ImageData PlanImageData(std::span<const EncodedImage> images) {
  ImageData data;
  for (const EncodedImage& image : images) {
    const std::uint64_t offset = AlignUp(data.size, kImageAlignment);
    data.offsets.push_back(offset);
    data.size = offset + image.bytes.size();
  }
  return data;
}

std::string Describe(const ImageHeader& header) {
  return std::to_string(header.width) + " x " + std::to_string(header.height) + " " +
         MimeType(header.format);
}

class MaterialReader {
 public:
  MaterialReader(std::span<const std::byte> file, const SectionRefs& sections, std::uint64_t name_bytes,
                 const std::string& path)
      : file_(file), sections_(sections), name_bytes_(name_bytes), path_(path) {}

  FrigMaterials Read(std::uint32_t part_count) {
    FrigMaterials read;
    read.images.reserve(static_cast<std::size_t>(sections_[kImages].count));
    std::uint64_t data_end = 0;
    for (std::size_t i = 0; i < sections_[kImages].count; ++i) read.images.push_back(ReadImage(i, data_end));
    CheckImageDataEnd(data_end);
    read.materials.reserve(static_cast<std::size_t>(sections_[kMaterials].count));
    for (std::size_t i = 0; i < sections_[kMaterials].count; ++i) {
      read.materials.push_back(ReadMaterial(i, read.images.size()));
    }
    read.part_materials.assign(part_count, -1);
    if (sections_[kPartMaterials].present) {
      for (std::size_t i = 0; i < part_count; ++i) {
        read.part_materials[i] = Index(FieldAt(kPartMaterials, i, 0), read.materials.size(),
                                       "'PMAT' part " + std::to_string(i) + " material");
      }
    }
    return read;
  }

 private:
  [[noreturn]] void Fail(IoErrorKind kind, std::uint64_t offset, std::string message) const {
    throw IoError(kind, path_, std::move(message), 0, static_cast<std::int64_t>(offset));
  }

  const std::byte* At(std::uint64_t offset) const { return file_.data() + offset; }

  std::uint64_t FieldAt(Section k, std::size_t i, std::uint64_t byte) const {
    return sections_[k].offset + kSectionKinds[k].element_size * std::uint64_t{i} + byte;
  }

  // The name at bytes 0..7 of element i: inside 'STRS', and all names
  // together no longer than it, so repeating one long name cannot inflate a
  // small file.
  std::string Name(Section k, std::size_t i, const std::string& what) {
    const std::uint32_t offset = Load32(At(FieldAt(k, i, 0)));
    const std::uint32_t length = Load32(At(FieldAt(k, i, 4)));
    const std::uint64_t strings_size = sections_[kStrings].count;
    name_bytes_ += length;
    if (std::uint64_t{offset} + length > strings_size || name_bytes_ > strings_size) {
      Fail(IoErrorKind::kIndexOutOfRange, FieldAt(k, i, 0),
           what + ": name [" + std::to_string(offset) + ", +" + std::to_string(length) +
               ") is outside the string table of " + std::to_string(strings_size) + " bytes or names overlap");
    }
    return std::string(reinterpret_cast<const char*>(At(sections_[kStrings].offset + offset)), length);
  }

  // An i32 index at `at`: -1 (none) or below `count`.
  std::int32_t Index(std::uint64_t at, std::size_t count, const std::string& what) const {
    const auto index = BitCast<std::int32_t>(Load32(At(at)));
    if (index < -1 || index >= static_cast<std::int64_t>(count)) {
      Fail(IoErrorKind::kIndexOutOfRange, at,
           what + " is " + std::to_string(index) + " of " + std::to_string(count));
    }
    return index;
  }

  float Finite(std::uint64_t at, const std::string& what) const {
    const float value = LoadFloat(At(at));
    if (!std::isfinite(value)) Fail(IoErrorKind::kNonFinite, at, what + " is not finite");
    return value;
  }

  Material ReadMaterial(std::size_t i, std::size_t image_count) {
    const std::string what = "'MATL' material " + std::to_string(i);
    Material material;
    material.name = Name(kMaterials, i, what);
    for (int c = 0; c < 4; ++c) {
      const std::uint64_t at = FieldAt(kMaterials, i, 8 + 4 * static_cast<std::uint64_t>(c));
      material.base_colour[c] = Finite(at, what + " base colour");
    }
    material.base_colour_image = Index(FieldAt(kMaterials, i, 24), image_count, what + " base colour image");
    material.normal_image = Index(FieldAt(kMaterials, i, 28), image_count, what + " normal image");
    const std::uint32_t alpha_mode = Load32(At(FieldAt(kMaterials, i, 32)));
    if (alpha_mode > kMaxAlphaMode) {
      Fail(IoErrorKind::kParse, FieldAt(kMaterials, i, 32),
           what + ": unknown alpha mode " + std::to_string(alpha_mode));
    }
    material.alpha_mode = static_cast<AlphaMode>(alpha_mode);
    material.alpha_cutoff = Finite(FieldAt(kMaterials, i, 36), what + " alpha cutoff");
    const std::uint32_t flags = Load32(At(FieldAt(kMaterials, i, 40)));
    if ((flags & ~kKnownMaterialFlags) != 0) {
      Fail(IoErrorKind::kParse, FieldAt(kMaterials, i, 40), what + ": unknown flags " + std::to_string(flags));
    }
    material.double_sided = (flags & kMaterialDoubleSided) != 0;
    material.roughness = Finite(FieldAt(kMaterials, i, 44), what + " roughness");
    return material;
  }

  // The header that the bytes themselves carry; ProbeImage's error, if any,
  // says which image and where its bytes start.
  ImageHeader Probe(std::span<const std::byte> bytes, std::uint64_t at, const std::string& what) const {
    try {
      return ProbeImage(bytes, path_);
    } catch (const IoError& error) {
      const auto within = static_cast<std::uint64_t>(std::max<std::int64_t>(error.offset(), 0));
      throw IoError(error.kind(), path_, what + ": " + error.message(), 0, static_cast<std::int64_t>(at + within));
    }
  }

  // `data_end`: where the previous image's bytes end in 'IMGB'.
  EncodedImage ReadImage(std::size_t i, std::uint64_t& data_end) {
    const std::string what = "'IMGS' image " + std::to_string(i);
    const std::byte* p = At(FieldAt(kImages, i, 0));
    EncodedImage image;
    image.name = Name(kImages, i, what);
    if (image.name.empty() || image.name.find_first_of("/\\") != std::string::npos) {
      Fail(IoErrorKind::kParse, FieldAt(kImages, i, 0),
           what + ": name '" + image.name + "' is not a plain file name");
    }
    const std::uint32_t format = Load32(p + 8);
    if (format > kMaxImageFormat) {
      Fail(IoErrorKind::kParse, FieldAt(kImages, i, 8), what + ": unknown format " + std::to_string(format));
    }
    const ImageHeader declared{static_cast<ImageFormat>(format), Load32(p + 12), Load32(p + 16)};
    const std::uint32_t length = Load32(p + 20);
    const std::uint64_t data_offset = Load64(p + 24);
    const std::uint64_t data_size = sections_[kImageBytes].count;
    const std::uint64_t next_data = AlignUp(data_end, kImageAlignment);
    if (data_offset != next_data) {
      Fail(IoErrorKind::kParse, FieldAt(kImages, i, 24),
           what + ": bytes at " + std::to_string(data_offset) + " in 'IMGB', expected " +
               std::to_string(next_data) + " (images follow each other, 8-aligned)");
    }
    if (length == 0 || data_offset > data_size || length > data_size - data_offset) {
      Fail(IoErrorKind::kTruncated, FieldAt(kImages, i, 20),
           what + ": " + std::to_string(length) + " bytes at " + std::to_string(data_offset) +
               " do not fit in 'IMGB' of " + std::to_string(data_size) + " bytes");
    }
    const std::uint64_t at = sections_[kImageBytes].offset + data_offset;
    const ImageHeader actual = Probe(std::span(At(at), length), at, what);
    if (actual.format != declared.format || actual.width != declared.width || actual.height != declared.height) {
      Fail(IoErrorKind::kParse, FieldAt(kImages, i, 8),
           what + " is declared " + Describe(declared) + " but its bytes are " + Describe(actual));
    }
    image.format = declared.format;
    image.width = declared.width;
    image.height = declared.height;
    image.bytes.resize(length);
    std::copy_n(reinterpret_cast<const std::uint8_t*>(At(at)), length, image.bytes.data());
    data_end = data_offset + length;
    return image;
  }

  // No bytes after the last image, so that 'IMGB' holds nothing unaccounted for.
  void CheckImageDataEnd(std::uint64_t data_end) const {
    const std::uint64_t data_size = sections_[kImageBytes].count;
    if (data_size != data_end) {
      Fail(IoErrorKind::kParse, sections_[kImageBytes].table_entry + kEntryByteSizeAt,
           "'IMGB' holds " + std::to_string(data_size) + " bytes but its images end at " +
               std::to_string(data_end));
    }
  }

  std::span<const std::byte> file_;
  const SectionRefs& sections_;
  std::uint64_t name_bytes_;
  const std::string& path_;
};

void WriteMaterial(const Material& material, NameRef name, Cursor& out) {
  out.U32(name.first);
  out.U32(name.second);
  for (int c = 0; c < 4; ++c) out.Float(material.base_colour[c]);
  out.U32(BitCast<std::uint32_t>(material.base_colour_image));
  out.U32(BitCast<std::uint32_t>(material.normal_image));
  out.U32(static_cast<std::uint32_t>(material.alpha_mode));
  out.Float(material.alpha_cutoff);
  out.U32(material.double_sided ? kMaterialDoubleSided : 0u);
  out.Float(material.roughness);
}

}  // namespace

void CheckMaterialCounts(const SectionRefs& sections, std::uint32_t part_count, const std::string& path) {
  const SectionRef& part_materials = sections[kPartMaterials];
  if (part_materials.present && part_materials.count != part_count) {
    throw IoError(IoErrorKind::kAbsurdCount, path,
                  "section 'PMAT' holds " + std::to_string(part_materials.count) +
                      " elements but META declares part_count " + std::to_string(part_count),
                  0, static_cast<std::int64_t>(part_materials.table_entry + kEntryCountAt));
  }
  if (sections[kImages].present != sections[kImageBytes].present) {
    const SectionRef& present = sections[kImages].present ? sections[kImages] : sections[kImageBytes];
    throw IoError(IoErrorKind::kParse, path, "sections 'IMGS' and 'IMGB' must come together", 0,
                  static_cast<std::int64_t>(present.table_entry));
  }
  for (const Section k : {kMaterials, kImages}) {
    if (sections[k].count > kMaxIndexedCount) {
      throw IoError(IoErrorKind::kAbsurdCount, path,
                    "section " + std::string(k == kMaterials ? "'MATL'" : "'IMGS'") + " holds " +
                        std::to_string(sections[k].count) + " elements, more than an i32 index can name",
                    0, static_cast<std::int64_t>(sections[k].table_entry + kEntryCountAt));
    }
  }
}

FrigMaterials ReadFrigMaterials(std::span<const std::byte> file, const SectionRefs& sections,
                                std::uint32_t part_count, std::uint64_t name_bytes, const std::string& path) {
  return MaterialReader(file, sections, name_bytes, path).Read(part_count);
}

void PlanMaterialSections(const Rig& rig, std::array<std::uint64_t, kSectionKindCount>& counts,
                          std::array<bool, kSectionKindCount>& present) {
  const bool has_materials = !rig.materials().empty();
  present[kMaterials] = present[kPartMaterials] = has_materials;
  counts[kMaterials] = rig.materials().size();
  counts[kPartMaterials] = has_materials ? rig.parts().size() : 0;
  present[kImages] = present[kImageBytes] = !rig.images().empty();
  counts[kImages] = rig.images().size();
  counts[kImageBytes] = PlanImageData(rig.images()).size;
}

void CheckMaterialsWritable(const Rig& rig, const std::string& path) {
  const auto refuse = [&](const std::string& message) { throw IoError(IoErrorKind::kInvalidRig, path, message); };
  for (const Material& material : rig.materials()) {
    const glm::vec4& colour = material.base_colour;
    if (!std::isfinite(colour.r) || !std::isfinite(colour.g) || !std::isfinite(colour.b) ||
        !std::isfinite(colour.a) || !std::isfinite(material.alpha_cutoff) || !std::isfinite(material.roughness)) {
      refuse("material '" + material.name + "' has a value that is not finite");
    }
  }
  for (const EncodedImage& image : rig.images()) {
    if (image.bytes.size() > std::numeric_limits<std::uint32_t>::max()) {
      refuse("image '" + image.name + "' is larger than .frig v1 allows (4 GiB)");
    }
    ImageHeader header;
    try {
      header = ProbeImage(std::as_bytes(std::span(image.bytes)), path);
    } catch (const IoError& error) {
      refuse("image '" + image.name + "': " + error.message());
    }
    if (header.format != image.format || header.width != image.width || header.height != image.height) {
      refuse("image '" + image.name + "' says " + Describe({image.format, image.width, image.height}) +
             " but its bytes are " + Describe(header));
    }
  }
}

void WriteMaterialSections(const Rig& rig, std::span<const NameRef> material_names,
                           std::span<const NameRef> image_names,
                           const std::array<std::uint64_t, kSectionKindCount>& offsets, std::byte* file) {
  if (!rig.materials().empty()) {
    Cursor materials(file + offsets[kMaterials]);
    for (std::size_t i = 0; i < rig.materials().size(); ++i) {
      WriteMaterial(rig.materials()[i], material_names[i], materials);
    }
    Cursor part_materials(file + offsets[kPartMaterials]);
    for (const Part& part : rig.parts()) part_materials.U32(BitCast<std::uint32_t>(part.material));
  }
  const ImageData data = PlanImageData(rig.images());
  Cursor entries(file + offsets[kImages]);
  for (std::size_t i = 0; i < rig.images().size(); ++i) {
    const EncodedImage& image = rig.images()[i];
    entries.U32(image_names[i].first);
    entries.U32(image_names[i].second);
    entries.U32(static_cast<std::uint32_t>(image.format));
    entries.U32(image.width);
    entries.U32(image.height);
    entries.U32(static_cast<std::uint32_t>(image.bytes.size()));
    entries.U64(data.offsets[i]);
    std::copy_n(reinterpret_cast<const std::byte*>(image.bytes.data()), image.bytes.size(),
                file + offsets[kImageBytes] + data.offsets[i]);
  }
}

}  // namespace facerig::frig_format
