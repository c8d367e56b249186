// A face template: a rig plus a small descriptor saying what its vertices
// are (parts, the registered region, the 68 landmark vertices, the eyelid and
// lip rims, rigid parts, vertex groups). The descriptor is data (JSON, see
// docs/templates.md), so a user's own template gets the same
// treatment as ICT-FaceKit or the built-in head; a template without one gets a
// descriptor derived from its mesh, and says what was derived.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "facerig/offline/landmarks/face_landmarks.h"
#include "facerig/runtime/rig.h"

namespace facerig {

class LandmarkDetector;

// Vertices [first, last] (inclusive, as ICT-FaceKit's README writes them).
struct VertexRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  std::uint32_t count() const { return last - first + 1; }
  bool operator==(const VertexRange&) const = default;
};

struct TemplatePart {
  std::string name;  // skin, eyes, lashes, teeth, tongue, mouth_socket, ...
  VertexRange vertices;
  bool operator==(const TemplatePart&) const = default;
};

// Recognises a shipped descriptor's rig without trusting its file name.
struct TemplateFingerprint {
  std::size_t vertex_count = 0;
  std::size_t triangle_count = 0;
  std::string neutral_checksum;  // 16 hex digits (FNV-1a of the neutral at 1e-4 units)
  bool operator==(const TemplateFingerprint&) const = default;
};
TemplateFingerprint FingerprintOf(const Rig& rig);

enum class TemplateInfoSource : std::uint8_t { kExplicit, kBesideRig, kShipped, kDerived };
const char* ToString(TemplateInfoSource source);

struct FaceTemplateInfo {
  std::string name;
  std::optional<TemplateFingerprint> fingerprint;
  std::vector<TemplatePart> parts;
  // The non-rigid ICP fits vertices [0, region.last]; the rest follow.
  VertexRange region;
  // dlib's 68 landmarks (Multi-PIE order); empty: detected on the neutral.
  std::vector<std::uint32_t> landmark_vertices;
  // Rim vertices; nullopt: derived from the expressions' openings.
  std::optional<std::vector<std::uint32_t>> eyelid_rim;
  std::optional<std::vector<std::uint32_t>> lip_rim;
  std::vector<std::string> rigid_parts;  // names from `parts`
  // Named vertex groups, e.g. "face": the region the transfer metrics measure.
  std::map<std::string, VertexRange> vertex_groups;

  // Where it came from, and which fields were derived rather than read.
  TemplateInfoSource source = TemplateInfoSource::kDerived;
  std::string source_path;
  std::vector<std::string> derived;

  // The group's range, or the region when the descriptor has no such group.
  VertexRange Group(const std::string& group_name) const;
  const TemplatePart* FindPart(const std::string& part_name) const;
};

struct FaceTemplate {
  Rig rig;
  FaceTemplateInfo info;
};

// The largest descriptor file read (shipped ones are a few kB).
inline constexpr std::uint64_t kMaxTemplateDescriptorBytes = std::uint64_t{16} << 20;

// Parses and validates a descriptor against `rig`: every index in range,
// every field of the right type; a fingerprint, if present, must match.
// \throw InvalidInputError naming the file, field and value (quoted short);
//        IoError for text over kMaxTemplateDescriptorBytes or JSON nested
//        deeper than kMaxJsonNesting (input_file.h).
FaceTemplateInfo ParseFaceTemplateInfo(const std::string& json_text, const Rig& rig, const std::string& file_name);
// Reads through ReadInputText (input_file.h): a regular file of at most
// kMaxTemplateDescriptorBytes. \throw IoError when it cannot; InvalidInputError as above.
FaceTemplateInfo LoadFaceTemplateInfo(const std::filesystem::path& path, const Rig& rig);
// The descriptor as JSON (source fields left out).
std::string FaceTemplateInfoToJson(const FaceTemplateInfo& info);

// Derived from the mesh: parts from the rig's part groups (else connected
// components, else one part), the region from the first part as before,
// rims left to the expressions. Landmarks are detected when `detector` is
// given, else left empty (detected later by TemplateLandmarkVertices).
FaceTemplateInfo DeriveFaceTemplateInfo(const Rig& rig, LandmarkDetector* detector = nullptr);

// Folders holding shipped descriptors: the source tree's data/templates and
// the installed share/facerig/templates (those that exist).
std::vector<std::filesystem::path> ShippedTemplateDirectories();

// The descriptor for a rig, in this order: `explicit_path` if not empty; the
// file beside the rig (<stem>.template.json, or template.json inside a
// template folder); a shipped descriptor whose fingerprint matches; derived.
FaceTemplateInfo ResolveFaceTemplateInfo(const Rig& rig, const std::filesystem::path& rig_path,
                                         const std::filesystem::path& explicit_path = {},
                                         const std::vector<std::filesystem::path>& shipped_dirs =
                                             ShippedTemplateDirectories());
// LoadRig + ResolveFaceTemplateInfo.
FaceTemplate LoadFaceTemplate(const std::filesystem::path& rig_path, const std::filesystem::path& explicit_info = {});

// The template vertex of each of dlib's 68 landmarks: the descriptor's, or
// detected on the neutral (nearest region vertex), recorded as derived.
// \throw LandmarkDetectionError (as LandmarkDetector::Detect).
std::vector<std::uint32_t> TemplateLandmarkVertices(const Rig& rig, FaceTemplateInfo& info, LandmarkDetector& detector);

// A target on the template's own topology (the same vertex count and
// triangles: ICT-FaceKit's identities, a rig written with
// --template-topology) needs no detection: its landmarks are the template's
// landmark vertices. nullopt when the topology differs or the descriptor has
// no landmarks.
std::optional<FaceLandmarks> LandmarksOnTemplateTopology(const Rig& template_rig, const FaceTemplateInfo& info,
                                                         std::span<const glm::vec3> target_positions,
                                                         std::span<const Triangle> target_triangles);

}  // namespace facerig
