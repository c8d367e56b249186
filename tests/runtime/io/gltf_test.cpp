#include "facerig/runtime/io/gltf.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/rig_builder.h"
#include "support/command_runner.h"
#include "support/base64.h"
#include "support/gltf_validator.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::byte>;
using nlohmann::json;

// What RigsEqual leaves out: UVs, neutral normals and normal deltas.
void RequireSameExtras(const Rig& a, const Rig& b) {
  REQUIRE(a.uvs().size() == b.uvs().size());
  for (std::size_t i = 0; i < a.uvs().size(); ++i) {
    REQUIRE(std::abs(a.uvs()[i].x - b.uvs()[i].x) <= 1e-6f);
    REQUIRE(std::abs(a.uvs()[i].y - b.uvs()[i].y) <= 1e-6f);
  }
  for (std::size_t i = 0; i < a.vertex_count(); ++i) {
    REQUIRE(glm::length(a.normals()[i] - b.normals()[i]) <= 1e-6f);
  }
  REQUIRE(a.has_normal_deltas() == b.has_normal_deltas());
  REQUIRE(a.all_shape_normal_deltas().size() == b.all_shape_normal_deltas().size());
  for (std::size_t i = 0; i < a.all_shape_normal_deltas().size(); ++i) {
    REQUIRE(a.all_shape_normal_deltas()[i] == b.all_shape_normal_deltas()[i]);
  }
}

void RequireRoundTrip(const Rig& rig, const fs::path& path) {
  WriteGltf(path, rig);
  const Rig back = ReadGltf(path);
  std::string difference;
  INFO(path.string());
  // Positions and deltas are stored as float32: bit-exact.
  REQUIRE(test::RigsEqual(rig, back, 0.0f, &difference));
  RequireSameExtras(rig, back);
}

Bytes ToBytes(const std::string& text) {
  Bytes bytes(text.size());
  std::memcpy(bytes.data(), text.data(), text.size());
  return bytes;
}

std::uint32_t Get32(const Bytes& bytes, std::size_t at) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, sizeof(value));
  return value;
}
void Put32(Bytes& bytes, std::size_t at, std::uint32_t value) { std::memcpy(bytes.data() + at, &value, 4); }

// The JSON chunk of a .glb and where its BIN chunk's data starts.
struct Glb {
  json document;
  std::size_t bin_start = 0;
};
Glb SplitGlb(const Bytes& bytes) {
  const std::uint32_t json_length = Get32(bytes, 12);
  const auto* text = reinterpret_cast<const char*>(bytes.data() + 20);
  return {json::parse(text, text + json_length), 20 + json_length + 8};
}

// Byte offset in the .glb of element `element` of `accessor`.
std::size_t ElementOffset(const Glb& glb, int accessor, std::size_t element, std::size_t element_size) {
  const json& a = glb.document["accessors"][accessor];
  const json& view = glb.document["bufferViews"][a["bufferView"].get<int>()];
  return glb.bin_start + view.value("byteOffset", std::size_t{0}) + a.value("byteOffset", std::size_t{0}) +
         element * element_size;
}

// Elements of a SCALAR unsigned accessor (16- or 32-bit) in `buffer`.
std::vector<std::uint32_t> ReadUnsigned(const json& document, const unsigned char* buffer, int accessor_index) {
  const json& accessor = document["accessors"][accessor_index];
  const json& view = document["bufferViews"][accessor["bufferView"].get<int>()];
  const unsigned char* data =
      buffer + view.value("byteOffset", std::size_t{0}) + accessor.value("byteOffset", std::size_t{0});
  const bool short_values = accessor["componentType"] == 5123;
  std::vector<std::uint32_t> values(accessor["count"].get<std::size_t>());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (short_values) {
      std::uint16_t value = 0;
      std::memcpy(&value, data + 2 * i, 2);
      values[i] = value;
    } else {
      std::memcpy(&values[i], data + 4 * i, 4);
    }
  }
  return values;
}

// Which rig vertex each of a written primitive's vertices is (extras.facerig.vertices).
std::vector<std::uint32_t> PrimitiveRigVertices(const Glb& glb, const Bytes& bytes, const json& primitive) {
  return ReadUnsigned(glb.document, reinterpret_cast<const unsigned char*>(bytes.data()) + glb.bin_start,
                      primitive["extras"]["facerig"]["vertices"].get<int>());
}
// Same for a .gltf whose buffer is a data URI.
std::vector<std::uint32_t> PrimitiveRigVertices(const json& document, const json& primitive) {
  const std::string uri = document["buffers"][0]["uri"];
  const std::vector<unsigned char> buffer = test::Base64Decode(std::string_view(uri).substr(uri.find(',') + 1));
  return ReadUnsigned(document, buffer.data(), primitive["extras"]["facerig"]["vertices"].get<int>());
}

// The kind of IoError that reading `path` throws (nullopt when it reads), and
// checks that the message names the file.
std::optional<IoErrorKind> ReadErrorKind(const fs::path& path) {
  try {
    ReadGltf(path);
  } catch (const IoError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find(path.string()) != std::string::npos);
    CHECK(e.path() == path.string());
    return e.kind();
  }
  return std::nullopt;
}

fs::path WriteCorpusFile(const std::string& name, const Bytes& bytes) {
  const fs::path path = test::OutputPath("gltf_malformed/" + name);
  fs::create_directories(path.parent_path());
  WriteFileAtomically(path, bytes);
  return path;
}
fs::path WriteCorpusFile(const std::string& name, const json& document) {
  return WriteCorpusFile(name, ToBytes(document.dump()));
}

std::string ToString(std::optional<IoErrorKind> kind) {
  return kind ? std::string(facerig::ToString(*kind)) : std::string("no error");
}

#define REQUIRE_READ_ERROR(path, expected_kind)                      \
  do {                                                               \
    const std::optional<IoErrorKind> kind_ = ReadErrorKind(path);    \
    INFO((path).filename().string() << " gave " << ToString(kind_)); \
    REQUIRE(kind_ == std::optional<IoErrorKind>(expected_kind));     \
  } while (false)

using test::NoTemporaryFilesIn;

// A small rig with what the grid lacks: mm units, Z up, three parts, names
// that need escaping and a shape with no entries. (No normal deltas: RawRig
// refuses an empty shape in a rig that has them.)
Rig MakeVariedRig() {
  RawRig raw = test::MakeGridRawRig(5, 3, false);
  raw.units = Units::kMillimetres;
  raw.up_axis = UpAxis::kZ;
  const auto third = static_cast<std::uint32_t>(raw.triangles.size() / 3);
  raw.parts = {
      {"lips upper", 0, third},
      {"jaw", third, third},
      {"skin \xC3\xA9t\xC3\xA9", 2 * third, static_cast<std::uint32_t>(raw.triangles.size()) - 2 * third}};
  raw.shapes[0].name = "jawOpen";
  raw.shapes[1].name = "mouthSmile_L";
  raw.shapes[2].name = "eye Blink \"R\"";
  RawBlendShape empty;
  empty.name = "unused";
  raw.shapes.push_back(std::move(empty));
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  INFO(problem);
  REQUIRE(rig);
  return std::move(*rig);
}

TEST_CASE("gltf: round trip of a grid rig, .glb and .gltf", "[gltf]") {
  const bool normal_deltas = GENERATE(false, true);
  const std::string extension = GENERATE(std::string(".glb"), std::string(".gltf"));
  const Rig rig = test::MakeGridRig(7, 5, normal_deltas);
  RequireRoundTrip(rig,
                   test::OutputPath(std::string("gltf_grid_") + (normal_deltas ? "n" : "p") + extension));
}

TEST_CASE("gltf: keeps units, up axis, part and shape names, and empty shapes", "[gltf]") {
  const Rig rig = MakeVariedRig();
  for (const char* name : {"gltf_varied.glb", "gltf_varied.gltf"}) {
    const fs::path path = test::OutputPath(name);
    RequireRoundTrip(rig, path);
    const Rig back = ReadGltf(path);
    CHECK(back.units() == Units::kMillimetres);
    CHECK(back.up_axis() == UpAxis::kZ);
    REQUIRE(back.parts().size() == 3);
    CHECK(back.parts()[2].name == "skin \xC3\xA9t\xC3\xA9");
    REQUIRE(back.FindShape("eye Blink \"R\""));
    REQUIRE(back.FindShape("unused"));
    CHECK(back.shape(*back.FindShape("unused")).vertex_indices.empty());
  }
}

TEST_CASE("gltf: parts on their own vertices read back as the rig: shared, unused and out-of-order vertices",
          "[gltf]") {
  RawRig raw = test::MakeGridRawRig(6, 4, true);
  // The first part uses the highest vertices, the parts share a column, and
  // one vertex is on no triangle.
  const auto half = static_cast<std::uint32_t>(raw.triangles.size() / 2);
  std::rotate(raw.triangles.begin(), raw.triangles.begin() + half, raw.triangles.end());
  raw.parts = {{"upper", 0, static_cast<std::uint32_t>(raw.triangles.size()) - half},
               {"lower", static_cast<std::uint32_t>(raw.triangles.size()) - half, half}};
  raw.positions.emplace_back(9.0f, 9.0f, 9.0f);
  raw.uvs.emplace_back(0.5f, 0.5f);
  raw.shapes[0].vertex_indices.push_back(static_cast<std::uint32_t>(raw.positions.size() - 1));
  raw.shapes[0].position_deltas.emplace_back(0.0f, 1.0f, 0.0f);
  raw.shapes[0].normal_deltas.emplace_back(0.0f, 0.0f, 0.0f);
  std::string problem;
  const std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  INFO(problem);
  REQUIRE(rig);
  for (const char* name : {"gltf_parts.glb", "gltf_parts.gltf"}) RequireRoundTrip(*rig, test::OutputPath(name));
  const Mesh mesh = ReadGltfMesh(test::OutputPath("gltf_parts.glb"));
  CHECK(mesh.positions.size() == rig->vertex_count());
  CHECK(mesh.triangles.size() == rig->triangle_count());
}

TEST_CASE("gltf: file layout: sparse targets, extras, node transform", "[gltf]") {
  const Rig rig = MakeVariedRig();
  const fs::path path = test::OutputPath("gltf_layout.gltf");
  WriteGltf(path, rig);
  const json document = json::parse(ReadFileText(path));

  CHECK(document["asset"]["generator"] == "facerig");
  CHECK(document["asset"]["version"] == "2.0");
  REQUIRE(document["buffers"].size() == 1);
  CHECK(document["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0) ==
        0);

  const json& node = document["nodes"][0];
  CHECK(node["scale"] == json::array({0.001, 0.001, 0.001}));
  REQUIRE(node["rotation"].size() == 4);
  CHECK(node["rotation"][0].get<double>() == Approx(-std::sqrt(0.5)));
  CHECK(node["rotation"][3].get<double>() == Approx(std::sqrt(0.5)));

  REQUIRE(document["meshes"].size() == 1);
  const json& mesh = document["meshes"][0];
  CHECK(mesh["extras"]["facerig"]["units"] == "mm");
  CHECK(mesh["extras"]["facerig"]["up"] == "Z");
  CHECK(mesh["extras"]["facerig"]["parts"] == json::array({"lips upper", "jaw", "skin \xC3\xA9t\xC3\xA9"}));
  CHECK(mesh["extras"]["targetNames"].size() == rig.shape_count());
  CHECK(mesh["weights"] == json(std::vector<double>(rig.shape_count(), 0.0)));

  const json& primitives = mesh["primitives"];
  REQUIRE(primitives.size() == 3);
  std::set<int> position_accessors;
  for (std::size_t p = 0; p < primitives.size(); ++p) {
    // Each part on its own vertices: those its triangles use, named by rig index.
    const json& primitive = primitives[p];
    CHECK(primitive["mode"] == 4);
    CHECK(primitive["attributes"].contains("TEXCOORD_0"));
    position_accessors.insert(primitive["attributes"]["POSITION"].get<int>());
    const std::vector<std::uint32_t> rig_vertex = PrimitiveRigVertices(document, primitive);
    const Part& part = rig.parts()[p];
    std::set<std::uint32_t> used;
    for (const Triangle& t : rig.triangles().subspan(part.first_triangle, part.triangle_count)) {
      used.insert(t.begin(), t.end());
    }
    CHECK(rig_vertex == std::vector<std::uint32_t>(used.begin(), used.end()));
    CHECK(document["accessors"][primitive["attributes"]["POSITION"].get<int>()]["count"] == rig_vertex.size());

    REQUIRE(primitive["targets"].size() == rig.shape_count());
    for (std::size_t s = 0; s < rig.shape_count(); ++s) {
      const json& target = primitive["targets"][s];
      CHECK_FALSE(target.contains("NORMAL"));
      const json& accessor = document["accessors"][target["POSITION"].get<int>()];
      CHECK_FALSE(accessor.contains("bufferView"));
      CHECK(accessor["count"] == rig_vertex.size());
      CHECK(accessor.contains("min"));
      CHECK(accessor.contains("max"));
      std::size_t entries = 0;
      for (std::uint32_t v : rig.shape(s).vertex_indices) entries += used.count(v);
      if (entries == 0) {
        CHECK_FALSE(accessor.contains("sparse"));  // all zero, and valid without sparse
      } else {
        CHECK(accessor["sparse"]["count"] == entries);
        CHECK(accessor["sparse"]["indices"]["componentType"] == 5125);
      }
    }
  }
  CHECK(position_accessors.size() == primitives.size());

  // With normal deltas, each target also has a sparse NORMAL accessor.
  WriteGltf(path, test::MakeGridRig(4, 2, true));
  const json with_normals = json::parse(ReadFileText(path));
  for (const json& target : with_normals["meshes"][0]["primitives"][0]["targets"]) {
    REQUIRE(target.contains("NORMAL"));
    const json& accessor = with_normals["accessors"][target["NORMAL"].get<int>()];
    CHECK_FALSE(accessor.contains("bufferView"));
    CHECK(accessor.contains("sparse"));
  }
}

TEST_CASE("gltf: stores UVs with V flipped", "[gltf]") {
  const Rig rig = test::MakeGridRig(3, 0);
  const fs::path path = test::OutputPath("gltf_uv.glb");
  WriteGltf(path, rig);
  const Bytes bytes = ReadFileBytes(path);
  const Glb glb = SplitGlb(bytes);
  for (const json& primitive : glb.document["meshes"][0]["primitives"]) {
    const int uv_accessor = primitive["attributes"]["TEXCOORD_0"];
    const std::vector<std::uint32_t> rig_vertex = PrimitiveRigVertices(glb, bytes, primitive);
    for (std::size_t i = 0; i < rig_vertex.size(); ++i) {
      float stored_v = 0.0f;
      std::memcpy(&stored_v, bytes.data() + ElementOffset(glb, uv_accessor, i, 8) + 4, 4);
      CHECK(stored_v == Approx(1.0f - rig.uvs()[rig_vertex[i]].y));
    }
  }
}

// A foreign file: dense targets, no extras, two primitives with their own
// vertices, one non-indexed.
TEST_CASE("gltf: reads dense targets, separate vertex sets and defaults", "[gltf]") {
  std::vector<unsigned char> data;
  auto append = [&data](const void* p, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(p);
    data.insert(data.end(), bytes, bytes + size);
  };
  const float quad[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const float triangle[3][3] = {{2, 0, 0}, {3, 0, 0}, {2, 1, 0}};
  const float quad_target[4][3] = {{0, 0, 0}, {0, 0, 0.5f}, {0, 0, 0}, {0.25f, 0, 0}};
  const float triangle_target[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, -1}};
  const unsigned char indices[8] = {0, 1, 2, 0, 2, 3, 0, 0};  // padded to 4 bytes
  append(quad, sizeof(quad));                                 // 0: 48 bytes
  append(triangle, sizeof(triangle));                         // 48: 36
  append(quad_target, sizeof(quad_target));                   // 84: 48
  append(triangle_target, sizeof(triangle_target));           // 132: 36
  append(indices, sizeof(indices));                           // 168: 6 (+2)
  auto view = [](std::size_t offset, std::size_t length) {
    return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
  };
  auto vec3 = [](int bufferView, int count) {
    return json{{"bufferView", bufferView}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}};
  };
  json document = {
      {"asset", {{"version", "2.0"}}},
      {"buffers",
       {{{"byteLength", data.size()}, {"uri", "data:application/octet-stream;base64," + test::Base64Encode(data)}}}},
      {"bufferViews", {view(0, 48), view(48, 36), view(84, 48), view(132, 36), view(168, 6)}},
      {"accessors",
       {vec3(0, 4),
        vec3(1, 3),
        vec3(2, 4),
        vec3(3, 3),
        {{"bufferView", 4}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}}}, {"indices", 4}, {"targets", {{{"POSITION", 2}}}}},
           {{"attributes", {{"POSITION", 1}}}, {"targets", {{{"POSITION", 3}}}}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  const fs::path path = WriteCorpusFile("foreign.gltf", document);
  const Rig rig = ReadGltf(path);
  REQUIRE(rig.vertex_count() == 7);
  REQUIRE(rig.triangle_count() == 3);
  CHECK(rig.triangles()[2] == Triangle{4, 5, 6});
  CHECK(rig.units() == Units::kMetres);
  CHECK(rig.up_axis() == UpAxis::kY);
  REQUIRE(rig.parts().size() == 2);
  CHECK(rig.parts()[0].name == "primitive0");
  CHECK(rig.parts()[1].name == "primitive1");
  CHECK(rig.uvs().empty());
  REQUIRE(rig.shape_count() == 1);
  const BlendShapeView shape = rig.shape(0);
  CHECK(shape.name == "target0");
  // Exact zeros are dropped from dense targets.
  REQUIRE(shape.vertex_indices.size() == 3);
  CHECK(shape.vertex_indices[0] == 1);
  CHECK(shape.vertex_indices[1] == 3);
  CHECK(shape.vertex_indices[2] == 6);
  CHECK(shape.position_deltas[2] == glm::vec3(0, 0, -1));

  // Separate vertex sets whose primitives disagree about their targets cannot merge.
  document["meshes"][0]["primitives"][1]["targets"] = json::array();
  REQUIRE_READ_ERROR(WriteCorpusFile("target_count_mismatch.gltf", document), IoErrorKind::kParse);
}

TEST_CASE("gltf: reader refuses malformed files with the right error", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 2, true);
  const fs::path good_glb = test::OutputPath("gltf_corpus_source.glb");
  const fs::path good_gltf = test::OutputPath("gltf_corpus_source.gltf");
  WriteGltf(good_glb, rig);
  WriteGltf(good_gltf, rig);
  const Bytes glb_bytes = ReadFileBytes(good_glb);
  const json gltf = json::parse(ReadFileText(good_gltf));
  const json& primitive = gltf["meshes"][0]["primitives"][0];
  const int position = primitive["attributes"]["POSITION"];

  SECTION("empty files") {
    REQUIRE_READ_ERROR(WriteCorpusFile("empty.glb", Bytes{}), IoErrorKind::kEmpty);
    REQUIRE_READ_ERROR(WriteCorpusFile("empty.gltf", Bytes{}), IoErrorKind::kEmpty);
  }
  SECTION("missing file and unknown extension") {
    REQUIRE_READ_ERROR(test::OutputPath("gltf_malformed/does_not_exist.glb"), IoErrorKind::kOpenFailed);
    REQUIRE_READ_ERROR(WriteCorpusFile("mesh.fbx", glb_bytes), IoErrorKind::kUnsupportedFormat);
  }
  SECTION("random bytes and wrong magic") {
    std::mt19937 random(7);
    Bytes noise(1000);
    for (std::byte& b : noise) b = static_cast<std::byte>(random() & 0xFFu);
    noise[0] = std::byte{'x'};
    REQUIRE_READ_ERROR(WriteCorpusFile("random.glb", noise), IoErrorKind::kBadMagic);
    REQUIRE_READ_ERROR(WriteCorpusFile("random.gltf", noise), IoErrorKind::kBadMagic);
    Bytes wrong_magic = glb_bytes;
    wrong_magic[0] = std::byte{'G'};
    REQUIRE_READ_ERROR(WriteCorpusFile("wrong_magic.glb", wrong_magic), IoErrorKind::kBadMagic);
    REQUIRE_READ_ERROR(WriteCorpusFile("not_json.gltf", ToBytes("{ \"asset\": [1, 2,")), IoErrorKind::kParse);
    Bytes version3 = glb_bytes;
    Put32(version3, 4, 3);
    REQUIRE_READ_ERROR(WriteCorpusFile("version3.glb", version3), IoErrorKind::kUnsupportedVersion);
  }
  SECTION("truncated .glb") {
    for (std::size_t length :
         {std::size_t{3}, std::size_t{12}, std::size_t{19}, std::size_t{20}, std::size_t{64},
          glb_bytes.size() / 2, glb_bytes.size() - 4, glb_bytes.size() - 1}) {
      const Bytes truncated(glb_bytes.begin(), glb_bytes.begin() + static_cast<std::ptrdiff_t>(length));
      REQUIRE_READ_ERROR(WriteCorpusFile("truncated_" + std::to_string(length) + ".glb", truncated),
                         IoErrorKind::kTruncated);
    }
    Bytes long_json = glb_bytes;
    Put32(long_json, 12, Get32(glb_bytes, 8));  // JSON chunk longer than the file
    REQUIRE_READ_ERROR(WriteCorpusFile("long_json_chunk.glb", long_json), IoErrorKind::kTruncated);
  }
  SECTION("accessors and buffer views out of range") {
    json bad = gltf;
    bad["accessors"][position]["byteOffset"] = 400;
    REQUIRE_READ_ERROR(WriteCorpusFile("accessor_offset.gltf", bad), IoErrorKind::kIndexOutOfRange);
    bad = gltf;
    bad["accessors"][position]["count"] = rig.vertex_count() + 1;
    REQUIRE_READ_ERROR(WriteCorpusFile("accessor_count.gltf", bad), IoErrorKind::kIndexOutOfRange);
    bad = gltf;
    bad["bufferViews"][bad["accessors"][position]["bufferView"].get<int>()]["byteLength"] = 1 << 20;
    REQUIRE_READ_ERROR(WriteCorpusFile("view_length.gltf", bad), IoErrorKind::kIndexOutOfRange);
    bad = gltf;
    for (json& p : bad["meshes"][0]["primitives"]) p["attributes"]["POSITION"] = 999;
    REQUIRE_READ_ERROR(WriteCorpusFile("attribute_index.gltf", bad), IoErrorKind::kIndexOutOfRange);
    bad = gltf;
    bad["accessors"][primitive["targets"][0]["POSITION"].get<int>()]["sparse"]["values"]["byteOffset"] =
        1 << 24;
    REQUIRE_READ_ERROR(WriteCorpusFile("sparse_offset.gltf", bad), IoErrorKind::kIndexOutOfRange);
  }
  SECTION("compressed meshes (Draco, meshopt): no plain vertex data to read") {
    for (const char* extension : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
      json compressed = gltf;
      compressed["extensionsUsed"] = json::array({extension});
      compressed["extensionsRequired"] = json::array({extension});
      REQUIRE_READ_ERROR(WriteCorpusFile(std::string(extension) + ".gltf", compressed),
                         IoErrorKind::kUnsupportedFormat);
    }
  }
  SECTION("indices out of range") {
    Bytes bad = glb_bytes;
    const Glb glb = SplitGlb(glb_bytes);
    REQUIRE(glb.document["accessors"][primitive["indices"].get<int>()]["componentType"] == 5123);
    const std::size_t at = ElementOffset(glb, primitive["indices"], 4, 2);
    const auto too_big = static_cast<std::uint16_t>(rig.vertex_count());
    std::memcpy(bad.data() + at, &too_big, 2);
    REQUIRE_READ_ERROR(WriteCorpusFile("index_out_of_range.glb", bad), IoErrorKind::kIndexOutOfRange);
  }
  SECTION("non-finite values") {
    const Glb glb = SplitGlb(glb_bytes);
    Bytes bad = glb_bytes;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bad.data() + ElementOffset(glb, position, 5, 12) + 4, &nan, 4);
    REQUIRE_READ_ERROR(WriteCorpusFile("nan_position.glb", bad), IoErrorKind::kNonFinite);

    bad = glb_bytes;
    const json& target = glb.document["accessors"][primitive["targets"][1]["POSITION"].get<int>()];
    const json& values_view =
        glb.document["bufferViews"][target["sparse"]["values"]["bufferView"].get<int>()];
    const std::size_t at = glb.bin_start + values_view.value("byteOffset", std::size_t{0}) +
                           target["sparse"]["values"].value("byteOffset", std::size_t{0});
    const float inf = std::numeric_limits<float>::infinity();
    std::memcpy(bad.data() + at, &inf, 4);
    REQUIRE_READ_ERROR(WriteCorpusFile("inf_delta.glb", bad), IoErrorKind::kNonFinite);
  }
  SECTION("absurd counts") {
    json bad = gltf;
    bad["accessors"][position]["count"] = std::uint64_t{1} << 31;
    REQUIRE_READ_ERROR(WriteCorpusFile("absurd_count.gltf", bad), IoErrorKind::kAbsurdCount);
    bad = gltf;
    bad["accessors"][position]["count"] = std::uint64_t{1} << 40;
    bad["accessors"][position].erase("bufferView");
    REQUIRE_READ_ERROR(WriteCorpusFile("absurd_count_no_view.gltf", bad), IoErrorKind::kAbsurdCount);
    bad = gltf;
    json& target = bad["accessors"][primitive["targets"][0]["POSITION"].get<int>()];
    target["sparse"]["count"] = rig.vertex_count() + 1;
    REQUIRE_READ_ERROR(WriteCorpusFile("absurd_sparse_count.gltf", bad), IoErrorKind::kAbsurdCount);
  }
  SECTION("structural nonsense is a parse error") {
    json bad = gltf;
    bad["accessors"][position]["type"] = "VEC2";
    REQUIRE_READ_ERROR(WriteCorpusFile("position_vec2.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad["accessors"][position]["componentType"] = 5130;  // DOUBLE: not glTF 2.0
    REQUIRE_READ_ERROR(WriteCorpusFile("position_double.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    json shorter = bad["accessors"][position];
    shorter["count"] = shorter["count"].get<int>() - 1;
    bad["accessors"].push_back(shorter);
    bad["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = bad["accessors"].size() - 1;  // wrong count
    REQUIRE_READ_ERROR(WriteCorpusFile("target_count.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad["meshes"][0]["primitives"][1]["extras"].erase("facerig");  // a vertex map on some primitives only
    REQUIRE_READ_ERROR(WriteCorpusFile("vertex_map_partial.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    json short_map = bad["accessors"][bad["meshes"][0]["primitives"][1]["extras"]["facerig"]["vertices"].get<int>()];
    short_map["count"] = short_map["count"].get<int>() - 1;
    bad["accessors"].push_back(short_map);
    bad["meshes"][0]["primitives"][1]["extras"]["facerig"]["vertices"] = bad["accessors"].size() - 1;
    REQUIRE_READ_ERROR(WriteCorpusFile("vertex_map_count.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad["meshes"][0]["primitives"][1]["extras"]["facerig"]["vertices"] =
        bad["meshes"][0]["primitives"][1]["attributes"]["POSITION"];  // floats, not vertex numbers
    REQUIRE_READ_ERROR(WriteCorpusFile("vertex_map_type.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad["meshes"][0]["extras"]["facerig"]["units"] = "furlongs";
    REQUIRE_READ_ERROR(WriteCorpusFile("bad_units.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad["buffers"][0]["byteLength"] = 123456789;
    REQUIRE_READ_ERROR(WriteCorpusFile("buffer_length.gltf", bad), IoErrorKind::kParse);
    bad = gltf;
    bad.erase("meshes");
    REQUIRE_READ_ERROR(WriteCorpusFile("no_mesh.gltf", bad), IoErrorKind::kEmpty);
    bad = gltf;
    bad["meshes"][0]["extras"]["targetNames"] = json::array({"same", "same"});
    REQUIRE_READ_ERROR(WriteCorpusFile("duplicate_names.gltf", bad), IoErrorKind::kInvalidRig);
  }
}

// Single-byte corruptions anywhere in a .glb, and in the digits of a .gltf:
// each must read or throw IoError, nothing else.
TEST_CASE("gltf: reader survives corrupted files", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 2, true);
  const fs::path source = test::OutputPath("gltf_fuzz_source.glb");
  WriteGltf(source, rig);
  const Bytes glb = ReadFileBytes(source);
  std::mt19937 random(2024);
  const fs::path path = test::OutputPath("gltf_malformed/fuzz.glb");
  fs::create_directories(path.parent_path());
  int errors = 0;
  for (int i = 0; i < 400; ++i) {
    Bytes bad = glb;
    const std::size_t at = random() % bad.size();
    bad[at] = static_cast<std::byte>(random() & 0xFFu);
    WriteFileAtomically(path, bad);
    INFO("byte " << at);
    try {
      ReadGltf(path);
    } catch (const IoError&) {
      ++errors;
    }
  }
  CHECK(errors > 0);

  const fs::path text_source = test::OutputPath("gltf_fuzz_source.gltf");
  WriteGltf(text_source, rig);
  const std::string text = ReadFileText(text_source);
  const std::size_t json_end = text.find("\"data:");  // corrupt the JSON, not the base64
  const fs::path text_path = test::OutputPath("gltf_malformed/fuzz.gltf");
  for (int i = 0; i < 300; ++i) {
    std::string bad = text;
    const std::size_t at = random() % json_end;
    bad[at] = "0123456789-e.,:[]{}\"9"[random() % 21];
    WriteFileAtomically(text_path, std::string_view(bad));
    INFO("char " << at);
    try {
      ReadGltf(text_path);
    } catch (const IoError&) {
    }
  }
}

TEST_CASE("gltf: writing is atomic", "[gltf]") {
  const Rig rig = test::MakeGridRig(4, 2);
  const fs::path dir = test::OutputPath("gltf_atomic");
  fs::remove_all(dir);
  fs::create_directories(dir);

  SECTION("into a missing directory: kWriteFailed, nothing created") {
    const fs::path missing = dir / "missing" / "rig.glb";
    try {
      WriteGltf(missing, rig);
      FAIL("writing into a missing directory succeeded");
    } catch (const IoError& e) {
      CHECK(e.kind() == IoErrorKind::kWriteFailed);
      CHECK(e.path() == missing.string());
    }
    CHECK_FALSE(fs::exists(dir / "missing"));
    CHECK(fs::is_empty(dir));
  }
  SECTION("an existing file is replaced only on success") {
    const fs::path path = dir / "rig.gltf";
    WriteGltf(path, test::MakeGridRig(3, 1));
    const std::string before = ReadFileText(path);
    // A rig with no vertices cannot be written; the old file must survive.
    CHECK_THROWS_AS(WriteGltf(path, Rig()), IoError);
    CHECK(ReadFileText(path) == before);
    WriteGltf(path, rig);
    CHECK(ReadGltf(path).vertex_count() == rig.vertex_count());
    CHECK(NoTemporaryFilesIn(dir));
  }
  SECTION("a directory in the way is not clobbered") {
    const fs::path path = dir / "taken.glb";
    fs::create_directories(path / "inside");
    CHECK_THROWS_AS(WriteGltf(path, rig), IoError);
    CHECK(fs::is_directory(path / "inside"));
    CHECK(NoTemporaryFilesIn(dir));
  }
  SECTION("unknown extension") {
    try {
      WriteGltf(dir / "rig.fbx", rig);
      FAIL("wrote an .fbx");
    } catch (const IoError& e) {
      CHECK(e.kind() == IoErrorKind::kUnsupportedFormat);
    }
    CHECK(fs::is_empty(dir));
  }
}


TEST_CASE("gltf: files pass the Khronos validator", "[gltf][gltf-validator]") {
  const fs::path grid_glb = test::OutputPath("gltf_validate_grid.glb");
  const fs::path grid_gltf = test::OutputPath("gltf_validate_grid.gltf");
  const fs::path varied_glb = test::OutputPath("gltf_validate_varied.glb");
  WriteGltf(grid_glb, test::MakeGridRig(8, 6, false));
  WriteGltf(grid_gltf, test::MakeGridRig(8, 6, true));
  WriteGltf(varied_glb, MakeVariedRig());
  test::RequireValidatorAccepts(grid_glb);
  test::RequireValidatorAccepts(grid_gltf);
  test::RequireValidatorAccepts(varied_glb);
}

TEST_CASE("gltf: round trip of the ICT-FaceKit rig (shared data)", "[gltf][shared-data]") {
  const Rig& rig = test::IctRig();
  REQUIRE(rig.shape_count() == 53);
  const fs::path path = test::OutputPath("gltf_ict.glb");
  RequireRoundTrip(rig, path);
  test::RequireValidatorAccepts(path);
}

}  // namespace
}  // namespace facerig
