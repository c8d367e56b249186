// .frig and materials: the MATL, PMAT, IMGS and IMGB sections round-trip,
// load as the GLB of the same rig does, and refuse hostile edits with the
// right error; files without them still load.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/rig_builder.h"
#include "frig_bytes.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace test::frig_bytes;

// Field offsets within a MATL element and an IMGS entry (frig.h).
constexpr std::uint64_t kMaterialSize = 48;
constexpr std::uint64_t kBaseColourImageAt = 24;
constexpr std::uint64_t kNormalImageAt = 28;
constexpr std::uint64_t kAlphaModeAt = 32;
constexpr std::uint64_t kFlagsAt = 40;
constexpr std::uint64_t kRoughnessAt = 44;
constexpr std::uint64_t kImageEntrySize = 32;
constexpr std::uint64_t kImageWidthAt = 12;
constexpr std::uint64_t kImageLengthAt = 20;
constexpr std::uint64_t kImageDataAt = 24;

// A 6 x 6 grid rig whose halves wear "skin" (a colour and a normal image) and
// "lens" (masked, double-sided, no image).
RawRig MakeMaterialRawRig() {
  RawRig raw = test::MakeGridRawRig(6, 3, true);
  raw.materials = {Material{.name = "skin",
                            .base_colour = {0.9f, 0.7f, 0.6f, 1.0f},
                            .base_colour_image = 0,
                            .normal_image = 1,
                            .roughness = 0.6f},
                   Material{.name = "lens",
                            .base_colour = {0.2f, 0.3f, 0.4f, 0.5f},
                            .alpha_mode = AlphaMode::kMask,
                            .alpha_cutoff = 0.3f,
                            .double_sided = true,
                            .roughness = 0.1f}};
  raw.images = {test::CheckerImage("skin.png", 8, 2, {200, 150, 120, 255}, {90, 40, 30, 255}),
                test::CheckerImage("skin_normal.png", 4, 1, {128, 128, 255, 255}, {128, 128, 255, 255})};
  REQUIRE(raw.parts.size() == 2);
  raw.parts[0].material = 0;
  raw.parts[1].material = 1;
  return raw;
}

Rig MakeMaterialRig() {
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(MakeMaterialRawRig(), &problem);
  INFO(problem);
  REQUIRE(rig);
  return std::move(*rig);
}

void RequireSameMaterials(const Rig& a, const Rig& b) {
  REQUIRE(a.materials().size() == b.materials().size());
  for (std::size_t i = 0; i < a.materials().size(); ++i) {
    const Material& ma = a.materials()[i];
    const Material& mb = b.materials()[i];
    CAPTURE(i, ma.name);
    CHECK(ma.name == mb.name);
    CHECK(ma.base_colour == mb.base_colour);
    CHECK(ma.base_colour_image == mb.base_colour_image);
    CHECK(ma.normal_image == mb.normal_image);
    CHECK(ma.alpha_mode == mb.alpha_mode);
    CHECK(ma.alpha_cutoff == mb.alpha_cutoff);
    CHECK(ma.double_sided == mb.double_sided);
    CHECK(ma.roughness == mb.roughness);
  }
  REQUIRE(a.images().size() == b.images().size());
  for (std::size_t i = 0; i < a.images().size(); ++i) {
    const EncodedImage& ia = a.images()[i];
    const EncodedImage& ib = b.images()[i];
    CAPTURE(i, ia.name);
    CHECK(ia.name == ib.name);
    CHECK(ia.format == ib.format);
    CHECK(ia.width == ib.width);
    CHECK(ia.height == ib.height);
    CHECK(ia.bytes == ib.bytes);
  }
  REQUIRE(a.parts().size() == b.parts().size());
  for (std::size_t i = 0; i < a.parts().size(); ++i) CHECK(a.parts()[i].material == b.parts()[i].material);
}

void RequireSameMesh(const Rig& a, const Rig& b) {
  std::string difference;
  const bool equal = test::RigsEqual(a, b, 0.0f, &difference);
  INFO(difference);
  REQUIRE(equal);
}

// Offset of field `at` of image entry i in IMGS.
std::uint64_t ImageField(const Bytes& bytes, std::size_t i, std::uint64_t at) {
  return Section(bytes, "IMGS").offset + kImageEntrySize * i + at;
}
std::uint64_t MaterialField(const Bytes& bytes, std::size_t i, std::uint64_t at) {
  return Section(bytes, "MATL").offset + kMaterialSize * i + at;
}
// File offset of image i's bytes.
std::uint64_t ImageBytesAt(const Bytes& bytes, std::size_t i) {
  return Section(bytes, "IMGB").offset + Get64(bytes, ImageField(bytes, i, kImageDataAt));
}

// The file an older facerig wrote for the same rig: the material sections
// (last in the table and in the file) dropped, and STRS kept whole.
Bytes WithoutMaterialSections(Bytes bytes) {
  const std::uint32_t count = Get32(bytes, 8);
  const SectionInfo strings = Section(bytes, "STRS");
  REQUIRE(strings.entry == 32 + 32 * std::uint64_t{count - 5});  // MATL, PMAT, IMGS, IMGB follow it
  Put32(bytes, 8, count - 4);
  bytes.resize(strings.offset + strings.count);
  Put64(bytes, 16, bytes.size());
  FixCrc(bytes);
  return bytes;
}

// The frig fuzzer's seed with materials (fuzz/seeds/frig/). To rewrite it after
// a deliberate change of the test rig, run
//   FACERIG_WRITE_FRIG_FUZZ_SEED=1 facerig_runtime_tests "The frig fuzz seed with materials loads"
TEST_CASE("The frig fuzz seed with materials loads", "[frig]") {
  const fs::path seed = fs::path(FACERIG_SOURCE_DIR) / "fuzz" / "seeds" / "frig" / "materials_v1.frig";
  if (std::getenv("FACERIG_WRITE_FRIG_FUZZ_SEED") != nullptr) WriteFrig(seed, MakeMaterialRig());
  const Rig loaded = ReadFrig(seed);
  CHECK(fs::file_size(seed) <= 65536);  // run-fuzz.sh's -max_len
  RequireSameMesh(loaded, MakeMaterialRig());
  RequireSameMaterials(loaded, MakeMaterialRig());
}

TEST_CASE("A .frig keeps materials, part materials and embedded images", "[frig]") {
  const Rig rig = MakeMaterialRig();
  const Bytes bytes = SerializeFrig(rig);
  for (const char* tag : {"MATL", "PMAT", "IMGS", "IMGB"}) {
    CAPTURE(tag);
    CHECK(Section(bytes, tag).offset % 16 == 0);
  }
  CHECK(Section(bytes, "MATL").count == 2);
  CHECK(Section(bytes, "PMAT").count == 2);
  REQUIRE(Section(bytes, "IMGS").count == 2);
  // The first image's length is not a multiple of 8, so the second one's
  // start shows the padding.
  REQUIRE(rig.images()[0].bytes.size() % 8 != 0);
  CHECK(ImageBytesAt(bytes, 0) % 8 == 0);
  CHECK(ImageBytesAt(bytes, 1) % 8 == 0);
  CHECK(ImageBytesAt(bytes, 1) > ImageBytesAt(bytes, 0) + rig.images()[0].bytes.size());

  const fs::path path = test::OutputPath("materials.frig");
  WriteFrig(path, rig);
  const Rig loaded = ReadFrig(path);
  RequireSameMesh(loaded, rig);
  RequireSameMaterials(loaded, rig);
  CHECK(loaded.parts()[0].material == 0);
  CHECK(loaded.parts()[1].material == 1);
  CHECK(SerializeFrig(loaded) == bytes);
}

TEST_CASE("A .frig loads as the GLB written from the same rig", "[frig][gltf]") {
  const Rig rig = MakeMaterialRig();
  const fs::path frig_path = test::OutputPath("looks_like_glb.frig");
  const fs::path glb_path = test::OutputPath("looks_like_glb.glb");
  WriteFrig(frig_path, rig);
  WriteGltf(glb_path, rig);
  const Rig from_frig = ReadFrig(frig_path);
  const Rig from_glb = ReadGltf(glb_path);
  REQUIRE(from_glb.materials().size() == 2);
  REQUIRE(from_glb.images().size() == 2);
  RequireSameMaterials(from_frig, from_glb);
  for (std::size_t i = 0; i < rig.parts().size(); ++i) {
    CHECK(from_frig.parts()[i].name == from_glb.parts()[i].name);
  }
}

TEST_CASE("A .frig without material sections loads with no materials", "[frig]") {
  const Rig rig = MakeMaterialRig();
  const Rig loaded = ParseFrig(WithoutMaterialSections(SerializeFrig(rig)), "older.frig");
  RequireSameMesh(loaded, rig);
  CHECK(loaded.materials().empty());
  CHECK(loaded.images().empty());
  for (const Part& part : loaded.parts()) CHECK(part.material == -1);

  // And a rig without materials is written without them.
  RawRig raw = MakeMaterialRawRig();
  raw.materials.clear();
  raw.images.clear();
  for (RawPart& part : raw.parts) part.material = -1;
  const Bytes plain = SerializeFrig(*RigBuilder::Build(std::move(raw)));
  for (const char* tag : {"MATL", "PMAT", "IMGS", "IMGB"}) CHECK_FALSE(FindSection(plain, tag));
}

TEST_CASE("A .frig with images but no materials keeps the images", "[frig]") {
  RawRig raw = MakeMaterialRawRig();
  raw.materials.clear();
  for (RawPart& part : raw.parts) part.material = -1;
  const Rig rig = *RigBuilder::Build(std::move(raw));
  const Bytes bytes = SerializeFrig(rig);
  CHECK_FALSE(FindSection(bytes, "MATL"));
  CHECK_FALSE(FindSection(bytes, "PMAT"));
  RequireSameMaterials(ParseFrig(bytes, "images_only.frig"), rig);
}

TEST_CASE("Malformed .frig material sections are refused with the right error", "[frig]") {
  const Bytes reference = SerializeFrig(MakeMaterialRig());
  Bytes bytes = reference;
  const auto refused = [&bytes](IoErrorKind kind, const std::string& names) {
    FixCrc(bytes);
    const IoError error = ParseError(bytes, "hostile/materials.frig");
    CHECK(error.kind() == kind);
    CHECK_THAT(error.message(), Contains(names));
    CHECK(error.offset() >= 0);
    return error;
  };

  SECTION("MATL count larger than the section") {
    Put64(bytes, Section(bytes, "MATL").entry + 8, 3);
    refused(IoErrorKind::kAbsurdCount, "'MATL'");
  }
  SECTION("IMGS count of 2^40") {
    Put64(bytes, Section(bytes, "IMGS").entry + 8, std::uint64_t{1} << 40);
    refused(IoErrorKind::kAbsurdCount, "'IMGS'");
  }
  SECTION("PMAT with fewer entries than parts") {
    const SectionInfo part_materials = Section(bytes, "PMAT");
    Put64(bytes, part_materials.entry + 8, 1);
    Put64(bytes, part_materials.entry + 24, 4);
    refused(IoErrorKind::kAbsurdCount, "'PMAT'");
  }
  SECTION("an image's length past the end of IMGB") {
    const std::uint64_t length_at = ImageField(bytes, 1, kImageLengthAt);
    Put32(bytes, length_at, Get32(bytes, length_at) + 1000);
    CHECK(refused(IoErrorKind::kTruncated, "'IMGS' image 1").offset() == static_cast<std::int64_t>(length_at));
  }
  SECTION("an image of 0 bytes") {
    Put32(bytes, ImageField(bytes, 0, kImageLengthAt), 0);
    refused(IoErrorKind::kTruncated, "'IMGS' image 0");
  }
  SECTION("an image that does not start where the previous one ends") {
    Put64(bytes, ImageField(bytes, 1, kImageDataAt), 0);  // overlapping image 0
    refused(IoErrorKind::kParse, "'IMGS' image 1");
  }
  SECTION("bytes after the last image") {
    const SectionInfo data = Section(bytes, "IMGB");
    bytes.resize(bytes.size() + 8, std::byte{0});
    Put64(bytes, data.entry + 8, data.count + 8);
    Put64(bytes, data.entry + 24, data.count + 8);
    Put64(bytes, 16, bytes.size());
    refused(IoErrorKind::kParse, "'IMGB'");
  }
  SECTION("bad image magic") {
    bytes[ImageBytesAt(bytes, 0)] = std::byte{'G'};
    CHECK(refused(IoErrorKind::kBadMagic, "'IMGS' image 0").offset() ==
          static_cast<std::int64_t>(ImageBytesAt(bytes, 0)));
  }
  SECTION("a width that the PNG header does not have") {
    Put32(bytes, ImageField(bytes, 0, kImageWidthAt), 9);
    refused(IoErrorKind::kParse, "declared 9 x 8 image/png but its bytes are 8 x 8 image/png");
  }
  SECTION("a JPEG format for PNG bytes") {
    Put32(bytes, ImageField(bytes, 1, 8), 1);
    refused(IoErrorKind::kParse, "'IMGS' image 1");
  }
  SECTION("an unknown image format") {
    Put32(bytes, ImageField(bytes, 1, 8), 7);
    refused(IoErrorKind::kParse, "unknown format 7");
  }
  SECTION("an image name with a folder") {
    const SectionInfo strings = Section(bytes, "STRS");
    const std::uint64_t name_at = strings.offset + Get32(bytes, ImageField(bytes, 1, 0));
    REQUIRE(static_cast<char>(bytes[name_at + 4]) == '_');  // "skin_normal.png"
    bytes[name_at + 4] = std::byte{'/'};
    refused(IoErrorKind::kParse, "not a plain file name");
  }
  SECTION("a material naming image 7 of 2") {
    Put32(bytes, MaterialField(bytes, 0, kBaseColourImageAt), 7);
    refused(IoErrorKind::kIndexOutOfRange, "'MATL' material 0 base colour image is 7 of 2");
  }
  SECTION("a material naming image -2") {
    Put32(bytes, MaterialField(bytes, 0, kNormalImageAt), static_cast<std::uint32_t>(-2));
    refused(IoErrorKind::kIndexOutOfRange, "normal image is -2 of 2");
  }
  SECTION("a part naming material 5 of 2") {
    Put32(bytes, Section(bytes, "PMAT").offset + 4, 5);
    refused(IoErrorKind::kIndexOutOfRange, "'PMAT' part 1 material is 5 of 2");
  }
  SECTION("a material name past the string table") {
    Put32(bytes, MaterialField(bytes, 1, 4), 1u << 30);
    refused(IoErrorKind::kIndexOutOfRange, "'MATL' material 1: name");
  }
  SECTION("an unknown alpha mode") {
    Put32(bytes, MaterialField(bytes, 1, kAlphaModeAt), 3);
    refused(IoErrorKind::kParse, "unknown alpha mode 3");
  }
  SECTION("unknown material flags") {
    Put32(bytes, MaterialField(bytes, 1, kFlagsAt), 3);
    refused(IoErrorKind::kParse, "unknown flags");
  }
  SECTION("a NaN roughness") {
    PutFloat(bytes, MaterialField(bytes, 0, kRoughnessAt), std::numeric_limits<float>::quiet_NaN());
    refused(IoErrorKind::kNonFinite, "'MATL' material 0 roughness");
  }
  SECTION("IMGB without IMGS") {
    std::memcpy(&bytes[Section(bytes, "IMGS").entry], "XIMG", 4);
    refused(IoErrorKind::kParse, "'IMGS' and 'IMGB'");
  }
  SECTION("the checksum still guards the image bytes") {
    bytes[ImageBytesAt(bytes, 1) + 40] ^= std::byte{0x10};
    const IoError error = ParseError(bytes);
    CHECK(error.kind() == IoErrorKind::kChecksumMismatch);
  }
}

TEST_CASE("A .frig reader survives a bit flip at every byte of a file with materials", "[frig]") {
  // As for the mesh sections: the result is an IoError or a rig that
  // validates, never a crash.
  const Bytes reference = SerializeFrig(MakeMaterialRig());
  const std::uint64_t first = Section(reference, "STRS").offset;  // the mesh sections have their own test
  const FlipSweep sweep = FlipEveryByte(reference, first);
  INFO(sweep.first_invalid);
  CHECK(sweep.first_invalid.empty());
  CHECK(sweep.refused > 0);
  CHECK(sweep.accepted > 0);  // colours, names and pixel data
}

TEST_CASE("SerializeFrig refuses materials a reader could not load", "[frig]") {
  RawRig raw = MakeMaterialRawRig();
  SECTION("an image whose size disagrees with its PNG header") { raw.images[1].width = 5; }
  SECTION("image bytes that are not PNG or JPEG") { raw.images[0].bytes[1] = 'Q'; }
  SECTION("a non-finite base colour") { raw.materials[1].base_colour.g = std::numeric_limits<float>::infinity(); }
  const Rig rig = *RigBuilder::Build(std::move(raw));
  try {
    static_cast<void>(SerializeFrig(rig));
    FAIL("SerializeFrig wrote a rig that ReadFrig would refuse");
  } catch (const IoError& error) {
    CHECK(error.kind() == IoErrorKind::kInvalidRig);
  }
}

}  // namespace
}  // namespace facerig
