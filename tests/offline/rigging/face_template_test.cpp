// Template descriptors: the shipped ICT-FaceKit and built-in head ones, the
// fingerprint that picks a shipped one, derivation for a template without
// one, and the errors a bad descriptor gets.
#include "facerig/offline/rigging/face_template.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <catch2/catch.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"
#include "support/hostile_files.h"
#include "support/test_meshes.h"

namespace Catch {
template <>
struct StringMaker<facerig::VertexRange> {
  static std::string convert(const facerig::VertexRange& range) {
    return "[" + std::to_string(range.first) + ", " + std::to_string(range.last) + "]";
  }
};
}  // namespace Catch

namespace facerig {
namespace {

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

std::filesystem::path ShippedDir() {
  REQUIRE_FALSE(ShippedTemplateDirectories().empty());
  return ShippedTemplateDirectories().front();
}

// Two separate quads (no part groups): vertices 0-3 and 4-7.
Rig TwoQuads() {
  RawRig raw;
  for (float x : {0.0f, 2.0f}) {
    raw.positions.insert(raw.positions.end(), {{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}, {x, 1, 0}});
  }
  for (std::uint32_t base : {0u, 4u}) {
    raw.triangles.push_back({base, base + 1, base + 2});
    raw.triangles.push_back({base, base + 2, base + 3});
  }
  return RigBuilder::Build(raw).value();
}

// A minimal valid descriptor for TwoQuads with `field` replaced by `value` (JSON text).
std::string QuadsDescriptor(const std::string& field = "", const std::string& value = "") {
  std::map<std::string, std::string> fields{{"name", "\"quads\""},
                                            {"parts", R"([{"name": "skin", "first": 0, "last": 3}])"},
                                            {"region", R"({"first": 0, "last": 3})"}};
  if (!field.empty()) fields[field] = value;
  std::string text = "{";
  for (const auto& [key, json] : fields) text += (text.size() > 1 ? ", \"" : "\"") + key + "\": " + json;
  return text + "}";
}

void RequireRejected(const std::string& field, const std::string& value, const std::string& expected_in_message) {
  const Rig rig = TwoQuads();
  CAPTURE(field, value);
  REQUIRE_THROWS_AS(ParseFaceTemplateInfo(QuadsDescriptor(field, value), rig, "quads.template.json"),
                    InvalidInputError);
  try {
    ParseFaceTemplateInfo(QuadsDescriptor(field, value), rig, "quads.template.json");
  } catch (const InvalidInputError& error) {
    const std::string message = error.what();
    CAPTURE(message);
    CHECK(message.find("quads.template.json") != std::string::npos);
    CHECK(message.find(expected_in_message) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("(shared data) face template: ICT-FaceKit gets the shipped descriptor by its fingerprint",
          "[face_template][shared-data]") {
  const Rig& ict = test::IctRig();
  const FaceTemplateInfo info = ResolveFaceTemplateInfo(ict, test::IctDir());
  CHECK(info.source == TemplateInfoSource::kShipped);
  CHECK(info.source_path.ends_with("ict-facekit.template.json"));
  CHECK(info.name == "ICT-FaceKit");
  CHECK(info.derived.empty());
  CHECK(info.fingerprint == FingerprintOf(ict));
  // ICT-FaceKit's README: face [0:9408], head and neck to 11247, 17 geometries, 68 landmarks.
  CHECK(info.region == VertexRange{0, 11247});
  CHECK(info.Group("face") == VertexRange{0, 9408});
  CHECK(info.parts.size() == 17);
  REQUIRE(info.landmark_vertices.size() == kDlibLandmarkCount);
  CHECK(info.landmark_vertices.front() == 1225);
  CHECK(info.landmark_vertices[30] == 4857);  // nose tip
  CHECK(info.landmark_vertices.back() == 5966);
  CHECK(std::find(info.rigid_parts.begin(), info.rigid_parts.end(), "teeth") != info.rigid_parts.end());
  CHECK_FALSE(info.eyelid_rim.has_value());  // derived from the blinks
}

TEST_CASE("face template: a descriptor's fingerprint must match the rig", "[face_template]") {
  const Rig quads = TwoQuads();
  const TemplateFingerprint print = FingerprintOf(quads);
  CHECK(print.vertex_count == 8);
  CHECK(print.triangle_count == 4);
  CHECK(print.neutral_checksum.size() == 16);
  const std::string matching =
      QuadsDescriptor("fingerprint", R"({"vertex_count": 8, "triangle_count": 4, "neutral_checksum": ")" +
                                         print.neutral_checksum + "\"}");
  CHECK(ParseFaceTemplateInfo(matching, quads, "quads.template.json").fingerprint == print);

  // Moving one vertex by a millimetre's worth changes the checksum.
  RawRig moved = RigBuilder::ToRaw(quads);
  moved.positions[5].x += 0.01f;
  const Rig other = RigBuilder::Build(moved).value();
  CHECK(FingerprintOf(other).neutral_checksum != print.neutral_checksum);
  REQUIRE_THROWS_AS(ParseFaceTemplateInfo(matching, other, "quads.template.json"), InvalidInputError);

  // The shipped ICT descriptor is not taken for another mesh: a grid gets a derived one.
  const Rig grid = test::MakeGridRig(8, 1);
  CHECK(ResolveFaceTemplateInfo(grid, "").source == TemplateInfoSource::kDerived);
  REQUIRE_THROWS_WITH(LoadFaceTemplateInfo(ShippedDir() / "ict-facekit.template.json", grid),
                      Catch::Contains("fingerprint") && Catch::Contains("ict-facekit.template.json"));
}

TEST_CASE("face template: derived for a small mesh without one", "[face_template]") {
  const Rig quads = TwoQuads();
  const FaceTemplateInfo info = ResolveFaceTemplateInfo(quads, test::OutputPath("no_such_quads.obj"));
  CHECK(info.source == TemplateInfoSource::kDerived);
  // No part groups: the connected components, the first one is the region.
  REQUIRE(info.parts.size() == 2);
  CHECK(info.parts[0].vertices == VertexRange{0, 3});
  CHECK(info.parts[1].vertices == VertexRange{4, 7});
  CHECK(info.region == VertexRange{0, 3});
  CHECK(info.landmark_vertices.empty());  // no detector given: detected when building
  for (const char* field : {"parts", "region", "rims", "vertex_groups"}) {
    CHECK(std::find(info.derived.begin(), info.derived.end(), field) != info.derived.end());
  }
  // Part groups win over components: the grid's "left" group (from vertex 0) is the region.
  const Rig grid_rig = test::MakeGridRig(6, 1);
  const FaceTemplateInfo grid = DeriveFaceTemplateInfo(grid_rig);
  REQUIRE(grid.parts.size() == 2);
  CHECK(grid.parts[0].name == "left");
  CHECK(grid.region == grid.parts[0].vertices);
  CHECK(grid.region.last + 1 < grid_rig.vertex_count());
  // Written and read back, the derived descriptor is the same.
  const FaceTemplateInfo again = ParseFaceTemplateInfo(FaceTemplateInfoToJson(info), quads, "derived.json");
  CHECK(again.parts == info.parts);
  CHECK(again.region == info.region);
  CHECK(again.vertex_groups == info.vertex_groups);
  CHECK(again.fingerprint == info.fingerprint);
}

TEST_CASE("face template: explicit path first, then the file beside the rig", "[face_template]") {
  const Rig quads = TwoQuads();
  const std::filesystem::path folder = test::FreshOutputFolder("face_template_beside");
  std::ofstream(folder / "quads.template.json") << QuadsDescriptor("name", "\"beside\"");
  std::ofstream(folder / "explicit.json") << QuadsDescriptor("name", "\"explicit\"");
  const FaceTemplateInfo beside = ResolveFaceTemplateInfo(quads, folder / "quads.obj");
  CHECK(beside.source == TemplateInfoSource::kBesideRig);
  CHECK(beside.name == "beside");
  const FaceTemplateInfo given = ResolveFaceTemplateInfo(quads, folder / "quads.obj", folder / "explicit.json");
  CHECK(given.source == TemplateInfoSource::kExplicit);
  CHECK(given.name == "explicit");
  // A template folder holds template.json.
  std::filesystem::create_directories(folder / "rig_folder");
  std::ofstream(folder / "rig_folder" / "template.json") << QuadsDescriptor("name", "\"folder\"");
  CHECK(ResolveFaceTemplateInfo(quads, folder / "rig_folder").name == "folder");
}

TEST_CASE("face template: a bad descriptor is rejected naming the file, field and value", "[face_template]") {
  RequireRejected("region", R"({"first": 0, "last": 8})", "region.last");
  RequireRejected("region", R"({"first": 0, "last": 8})", "vertex 8 is out of range");
  RequireRejected("region", R"("all")", "'region'");
  RequireRejected("region", R"({"first": 2, "last": 3})", "region.first");
  RequireRejected("landmarks", "[0, 1, 99]", "landmarks[2]");
  RequireRejected("landmarks", "[0, 1, 2]", "expected 68");
  RequireRejected("parts", R"([{"name": "skin", "rig_part": "M_Face"}])", "no part 'M_Face'");
  RequireRejected("parts", R"([{"first": 0, "last": 3}])", "parts[0]");
  RequireRejected("rigid_parts", R"(["teeth"])", "rigid_parts[0]");
  RequireRejected("rims", R"({"eyelids": [1, -4]})", "rims.eyelids[1]");
  RequireRejected("vertex_groups", R"({"face": {"first": 3, "last": 1}})", "vertex_groups.face");
  RequireRejected("fingerprint", R"({"vertex_count": "eight"})", "fingerprint");
  RequireRejected("fingerprint", R"({"vertex_count": 3.2e41, "triangle_count": 1, "neutral_checksum": "x"})",
                  "fingerprint.vertex_count");
  const Rig rig = TwoQuads();
  REQUIRE_THROWS_WITH(ParseFaceTemplateInfo("{\"region\": ", rig, "broken.json"),
                      Catch::Contains("broken.json") && Catch::Contains("not JSON"));
  REQUIRE_THROWS_WITH(ParseFaceTemplateInfo("{}", rig, "empty.json"), Catch::Contains("'region'"));
  // nlohmann throws out_of_range, not parse_error, for a number beyond double (found by fuzzing).
  REQUIRE_THROWS_WITH(ParseFaceTemplateInfo("{\"region\": 7e425}", rig, "huge.json"),
                      Catch::Contains("huge.json") && Catch::Contains("not JSON"));
}

TEST_CASE("face template: the built-in head's descriptor is written beside it and shipped", "[face_template]") {
  const std::filesystem::path head_path = FACERIG_DEFAULT_HEAD;
  const Rig head = LoadRig(head_path);
  const FaceTemplateInfo info = ResolveFaceTemplateInfo(head, head_path);
  CHECK(info.source == TemplateInfoSource::kBesideRig);
  CHECK(info.name == "default-head");
  REQUIRE_FALSE(info.parts.empty());
  CHECK(info.parts[0].name == "skin");
  CHECK(info.region == info.parts[0].vertices);
  CHECK(info.rigid_parts.size() == 8);  // eyes (white, iris, pupil) and teeth
  // The committed copy in data/templates is the generated one, and a head
  // copied elsewhere finds it by its fingerprint.
  const std::filesystem::path generated = head_path.parent_path() / "default_head.template.json";
  CHECK(ReadText(generated) == ReadText(ShippedDir() / "default_head.template.json"));
  const FaceTemplateInfo shipped = ResolveFaceTemplateInfo(head, test::OutputPath("moved_head.frig"));
  CHECK(shipped.source == TemplateInfoSource::kShipped);
  CHECK(shipped.region == info.region);
}

TEST_CASE("face template: derived on the built-in head, landmarks by the detector", "[face_template][landmarks]") {
  const Rig head = LoadRig(FACERIG_DEFAULT_HEAD);
  LandmarkDetector detector;
  const FaceTemplateInfo info = DeriveFaceTemplateInfo(head, &detector);
  CHECK(info.source == TemplateInfoSource::kDerived);
  REQUIRE(info.parts.size() > 1);
  CHECK(info.region == info.parts[0].vertices);  // the skin
  REQUIRE(info.landmark_vertices.size() == kDlibLandmarkCount);
  CHECK(std::find(info.derived.begin(), info.derived.end(), "landmarks") != info.derived.end());
  for (std::uint32_t v : info.landmark_vertices) CHECK(v <= info.region.last);
  CHECK(std::set<std::uint32_t>(info.landmark_vertices.begin(), info.landmark_vertices.end()).size() >= 60);
  // The nose tip (landmark 30) is in front of the eye corners (36, 45): +Z faces forward.
  const auto z = [&](std::size_t landmark) { return head.positions()[info.landmark_vertices[landmark]].z; };
  CHECK(z(30) > z(36));
  CHECK(z(30) > z(45));
}

TEST_CASE("face template: hostile descriptors are refused with short errors naming the file and field",
          "[face_template][hostile]") {
  namespace fs = std::filesystem;
  const Rig rig = TwoQuads();
  const fs::path folder = test::FreshOutputFolder("face_template_hostile");
  const fs::path fifo = folder / "pipe.template.json";
  test::MakeFifo(fifo);
  CHECK(test::ErrorWithoutHanging(fifo, [&] { LoadFaceTemplateInfo(fifo, rig); }) ==
        fifo.string() + ": is a FIFO (named pipe), not a regular file");
  const fs::path device = folder / "zero.template.json";
  fs::create_symlink("/dev/zero", device);
  CHECK(test::ErrorWithoutHanging(device, [&] { LoadFaceTemplateInfo(device, rig); }) ==
        device.string() + ": is a character device, not a regular file");

  // Nesting is refused before parsing; the size cap before reading.
  REQUIRE_THROWS_WITH(ParseFaceTemplateInfo("{\"extras\": " + std::string(20000, '[') + "}", rig, "deep.json"),
                      "deep.json (byte 74): JSON nested deeper than 64 levels");
  const fs::path large = folder / "large.template.json";
  std::ofstream(large).put(' ');
  fs::resize_file(large, kMaxTemplateDescriptorBytes + 1);
  REQUIRE_THROWS_WITH(LoadFaceTemplateInfo(large, rig), Catch::Contains("larger than the limit of 16777216"));

  // A huge value, key or bad token is quoted short.
  const std::string huge(1 << 20, 'x');
  for (const std::string& text :
       {QuadsDescriptor("name", "[\"" + huge + "\"]"), QuadsDescriptor("vertex_groups", "{\"" + huge + "\": 3}"),
        QuadsDescriptor("rigid_parts", "[\"" + huge + "\"]"), QuadsDescriptor("region", "\"" + huge + "\""),
        "{\"region\": " + huge + "}"}) {
    try {
      ParseFaceTemplateInfo(text, rig, "huge.json");
      FAIL("accepted");
    } catch (const InvalidInputError& error) {
      const std::string message = error.what();
      CAPTURE(message.substr(0, 300));
      CHECK(message.rfind("huge.json: ", 0) == 0);
      CHECK(message.size() < 700);
    }
  }
  REQUIRE_THROWS_WITH(ParseFaceTemplateInfo(QuadsDescriptor("name", "[1, 2, 3]"), rig, "q.json"),
                      "q.json: field 'name': expected a string, got an array of 3 elements");
}

}  // namespace facerig
