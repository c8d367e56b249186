// Reading, validating and writing a template descriptor (face_template.h).
#include "facerig/offline/rigging/face_template.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

using nlohmann::json;

std::uint64_t Fnv1a(std::uint64_t hash, std::int64_t value) {
  for (int byte = 0; byte < 8; ++byte) {
    hash ^= static_cast<std::uint64_t>(value >> (8 * byte)) & 0xffu;
    hash *= 1099511628211ull;
  }
  return hash;
}

// A value for an error message: short however large the value is.
std::string Shown(const json& value) {
  const std::string count = std::to_string(value.size());
  if (value.is_array()) return "an array of " + count + (value.size() == 1 ? " element" : " elements");
  if (value.is_object()) return "an object of " + count + (value.size() == 1 ? " key" : " keys");
  return QuoteInput(value.dump(-1, ' ', false, json::error_handler_t::replace));
}

// Errors name the file, the field and the offending value, in a line or two.
class DescriptorReader {
 public:
  DescriptorReader(const Rig& rig, std::string file) : rig_(rig), file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw InvalidInputError(file_ + ": field '" + QuoteInput(field) +
                            "': " + QuoteInput(problem, 2 * kMaxQuotedInputBytes));
  }

  std::uint32_t Vertex(const json& value, const std::string& field) const {
    if (!value.is_number_integer()) Fail(field, "expected a vertex index, got " + Shown(value));
    const auto index = value.get<std::int64_t>();
    if (index < 0 || static_cast<std::uint64_t>(index) >= rig_.vertex_count()) {
      Fail(field, "vertex " + std::to_string(index) + " is out of range (the rig has " +
                      std::to_string(rig_.vertex_count()) + " vertices)");
    }
    return static_cast<std::uint32_t>(index);
  }

  // {"first": a, "last": b} or {"rig_part": "M_Face"}.
  VertexRange Range(const json& value, const std::string& field) const {
    if (!value.is_object()) Fail(field, "expected {\"first\", \"last\"} or {\"rig_part\"}, got " + Shown(value));
    if (value.contains("rig_part")) return RigPart(value["rig_part"], field + ".rig_part");
    if (!value.contains("first") || !value.contains("last")) Fail(field, "needs 'first' and 'last'");
    const VertexRange range{Vertex(value["first"], field + ".first"), Vertex(value["last"], field + ".last")};
    if (range.last < range.first) {
      Fail(field, "last " + std::to_string(range.last) + " is before first " + std::to_string(range.first));
    }
    return range;
  }

  std::vector<std::uint32_t> Vertices(const json& value, const std::string& field) const {
    if (!value.is_array()) Fail(field, "expected an array of vertex indices or \"derive\", got " + Shown(value));
    std::vector<std::uint32_t> vertices;
    for (std::size_t i = 0; i < value.size(); ++i) {
      vertices.push_back(Vertex(value[i], field + "[" + std::to_string(i) + "]"));
    }
    return vertices;
  }

  std::string String(const json& value, const std::string& field) const {
    if (!value.is_string()) Fail(field, "expected a string, got " + Shown(value));
    return value.get<std::string>();
  }

 private:
  VertexRange RigPart(const json& value, const std::string& field) const {
    const std::string name = String(value, field);
    for (const Part& part : rig_.parts()) {
      if (part.name == name && part.vertex_count > 0) {
        return {part.first_vertex, part.first_vertex + part.vertex_count - 1};
      }
    }
    Fail(field, "the rig has no part '" + name + "'");
  }

  const Rig& rig_;
  std::string file_;
};

void ReadFingerprint(const json& value, const Rig& rig, const DescriptorReader& reader, FaceTemplateInfo& info) {
  if (!value.is_object()) reader.Fail("fingerprint", "expected an object, got " + Shown(value));
  TemplateFingerprint print;
  // A count must be a non-negative integer: nlohmann converts a float such as
  // 3e41 to size_t without a check (undefined behaviour; found by fuzzing).
  const auto count = [&](const char* key) {
    const json& field = value.at(key);
    if (!field.is_number_unsigned()) reader.Fail(std::string("fingerprint.") + key, "expected a count, got " + Shown(field));
    return field.get<std::size_t>();
  };
  try {
    print.vertex_count = count("vertex_count");
    print.triangle_count = count("triangle_count");
    print.neutral_checksum = value.at("neutral_checksum").get<std::string>();
  } catch (const json::exception& error) {
    reader.Fail("fingerprint", QuoteInput(error.what()));
  }
  if (print != FingerprintOf(rig)) {
    const TemplateFingerprint actual = FingerprintOf(rig);
    reader.Fail("fingerprint", "the rig does not match (descriptor " + std::to_string(print.vertex_count) +
                                   " vertices, " + std::to_string(print.triangle_count) + " triangles, checksum " +
                                   print.neutral_checksum + "; rig " + std::to_string(actual.vertex_count) + ", " +
                                   std::to_string(actual.triangle_count) + ", " + actual.neutral_checksum + ")");
  }
  info.fingerprint = print;
}

void ReadParts(const json& doc, const DescriptorReader& reader, FaceTemplateInfo& info) {
  if (!doc.contains("parts")) return;
  const json& parts = doc["parts"];
  if (!parts.is_array()) reader.Fail("parts", "expected an array, got " + Shown(parts));
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string field = "parts[" + std::to_string(i) + "]";
    if (!parts[i].is_object() || !parts[i].contains("name")) reader.Fail(field, "needs a 'name'");
    info.parts.push_back({reader.String(parts[i]["name"], field + ".name"), reader.Range(parts[i], field)});
  }
}

std::optional<std::vector<std::uint32_t>> ReadRim(const json& rims, const char* key, const DescriptorReader& reader) {
  const std::string field = std::string("rims.") + key;
  if (!rims.contains(key) || rims[key] == "derive") return std::nullopt;
  return reader.Vertices(rims[key], field);
}

void ReadLandmarksAndRims(const json& doc, const DescriptorReader& reader, FaceTemplateInfo& info) {
  if (doc.contains("landmarks") && doc["landmarks"] != "derive") {
    info.landmark_vertices = reader.Vertices(doc["landmarks"], "landmarks");
    if (info.landmark_vertices.size() != kDlibLandmarkCount) {
      reader.Fail("landmarks", "expected " + std::to_string(kDlibLandmarkCount) + " vertices (dlib order), got " +
                                   std::to_string(info.landmark_vertices.size()));
    }
  }
  if (!doc.contains("rims")) return;
  const json& rims = doc["rims"];
  if (rims == "derive") return;
  if (!rims.is_object()) reader.Fail("rims", "expected an object or \"derive\", got " + Shown(rims));
  info.eyelid_rim = ReadRim(rims, "eyelids", reader);
  info.lip_rim = ReadRim(rims, "lips", reader);
}

void ReadGroups(const json& doc, const DescriptorReader& reader, FaceTemplateInfo& info) {
  if (doc.contains("rigid_parts")) {
    const json& rigid = doc["rigid_parts"];
    if (!rigid.is_array()) reader.Fail("rigid_parts", "expected an array of part names, got " + Shown(rigid));
    for (std::size_t i = 0; i < rigid.size(); ++i) {
      const std::string field = "rigid_parts[" + std::to_string(i) + "]";
      const std::string name = reader.String(rigid[i], field);
      if (!info.FindPart(name)) reader.Fail(field, "no part named '" + name + "' in 'parts'");
      info.rigid_parts.push_back(name);
    }
  }
  if (doc.contains("vertex_groups")) {
    const json& groups = doc["vertex_groups"];
    if (!groups.is_object()) reader.Fail("vertex_groups", "expected an object, got " + Shown(groups));
    for (const auto& [name, range] : groups.items()) {
      info.vertex_groups[name] = reader.Range(range, "vertex_groups." + name);
    }
  }
}

nlohmann::ordered_json RangeJson(VertexRange range) { return {{"first", range.first}, {"last", range.last}}; }

}  // namespace

FaceTemplateInfo ParseFaceTemplateInfo(const std::string& json_text, const Rig& rig, const std::string& file_name) {
  const DescriptorReader reader(rig, file_name);
  if (json_text.size() > kMaxTemplateDescriptorBytes) {
    throw IoError(IoErrorKind::kAbsurdCount, file_name,
                  std::to_string(json_text.size()) + " bytes (at most " +
                      std::to_string(kMaxTemplateDescriptorBytes) + ")");
  }
  CheckJsonNesting(json_text, file_name);
  json doc;
  try {
    doc = json::parse(json_text);
  } catch (const json::exception& error) {  // parse_error, and out_of_range for 1e999
    throw InvalidInputError(file_name + ": not JSON: " + QuoteInput(error.what()));
  }
  if (!doc.is_object()) reader.Fail("(top level)", "expected an object");
  FaceTemplateInfo info;
  if (doc.contains("name")) info.name = reader.String(doc["name"], "name");
  if (doc.contains("fingerprint")) ReadFingerprint(doc["fingerprint"], rig, reader, info);
  ReadParts(doc, reader, info);
  if (!doc.contains("region")) reader.Fail("region", "missing (the vertices the registration fits)");
  info.region = reader.Range(doc["region"], "region");
  // The registration fits a prefix of the vertex order.
  if (info.region.first != 0) reader.Fail("region.first", "must be 0, got " + std::to_string(info.region.first));
  ReadLandmarksAndRims(doc, reader, info);
  ReadGroups(doc, reader, info);
  info.source_path = file_name;
  return info;
}

FaceTemplateInfo LoadFaceTemplateInfo(const std::filesystem::path& path, const Rig& rig) {
  return ParseFaceTemplateInfo(ReadInputText(path, kMaxTemplateDescriptorBytes), rig, path.string());
}

TemplateFingerprint FingerprintOf(const Rig& rig) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const glm::vec3& p : rig.positions()) {
    for (int c = 0; c < 3; ++c) hash = Fnv1a(hash, std::llround(static_cast<double>(p[c]) * 1e4));
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return {rig.vertex_count(), rig.triangles().size(), hex};
}

std::string FaceTemplateInfoToJson(const FaceTemplateInfo& info) {
  using ordered = nlohmann::ordered_json;
  ordered doc;
  doc["name"] = info.name;
  if (info.fingerprint) {
    doc["fingerprint"] = {{"vertex_count", info.fingerprint->vertex_count},
                          {"triangle_count", info.fingerprint->triangle_count},
                          {"neutral_checksum", info.fingerprint->neutral_checksum}};
  }
  doc["parts"] = ordered::array();
  for (const TemplatePart& part : info.parts) {
    doc["parts"].push_back({{"name", part.name}, {"first", part.vertices.first}, {"last", part.vertices.last}});
  }
  doc["region"] = RangeJson(info.region);
  doc["landmarks"] = info.landmark_vertices.empty() ? ordered("derive") : ordered(info.landmark_vertices);
  doc["rims"] = {{"eyelids", info.eyelid_rim ? ordered(*info.eyelid_rim) : ordered("derive")},
                 {"lips", info.lip_rim ? ordered(*info.lip_rim) : ordered("derive")}};
  doc["rigid_parts"] = info.rigid_parts;
  doc["vertex_groups"] = ordered::object();
  for (const auto& [name, range] : info.vertex_groups) doc["vertex_groups"][name] = RangeJson(range);
  return doc.dump(2) + "\n";
}

VertexRange FaceTemplateInfo::Group(const std::string& group_name) const {
  const auto found = vertex_groups.find(group_name);
  return found != vertex_groups.end() ? found->second : region;
}

const TemplatePart* FaceTemplateInfo::FindPart(const std::string& part_name) const {
  for (const TemplatePart& part : parts) {
    if (part.name == part_name) return &part;
  }
  return nullptr;
}

const char* ToString(TemplateInfoSource source) {
  switch (source) {
    case TemplateInfoSource::kExplicit:
      return "explicit";
    case TemplateInfoSource::kBesideRig:
      return "beside the rig";
    case TemplateInfoSource::kShipped:
      return "shipped";
    case TemplateInfoSource::kDerived:
      return "derived";
  }
  return "?";
}

}  // namespace facerig
