// Raw, editable rig data and the builder that turns it into an immutable Rig.
//
// Readers and offline tools fill a RawRig (plain vectors), then call
// RigBuilder::Build, which validates it, fills what may be derived (neutral
// normals, part vertex spans, sorted shape entries) and returns the Rig.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

// One blend shape, sparse: vertex_indices need not be sorted (the builder
// sorts them) but must be unique. normal_deltas is empty or the same size as
// position_deltas.
struct RawBlendShape {
  std::string name;
  std::vector<std::uint32_t> vertex_indices;
  std::vector<glm::vec3> position_deltas;
  std::vector<glm::vec3> normal_deltas;
};

// Parts here are triangle ranges only; the builder derives their vertex spans.
struct RawPart {
  std::string name;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  std::int32_t material = -1;  // index into RawRig::materials; -1: none
};

struct RawRig {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty: computed (area-weighted) by the builder
  std::vector<Triangle> triangles;
  std::vector<glm::vec2> uvs;      // empty, or one per vertex
  // Empty, or ranges that tile [0, triangles.size()) in order. Empty: one part "mesh".
  std::vector<RawPart> parts;
  std::vector<Material> materials;
  std::vector<EncodedImage> images;  // what the materials show
  Units units = Units::kUnknown;
  UpAxis up_axis = UpAxis::kY;
  // Either every non-empty shape has normal deltas or none has.
  std::vector<RawBlendShape> shapes;

  // True when the data can be built. On failure, `problem` (if given) names
  // the first offending element, e.g. "shape 'jawOpen': vertex index 30000 >= 16608".
  bool Validate(std::string* problem = nullptr) const;
};

// Builds a sparse shape from dense per-vertex deltas, keeping the vertices
// whose position delta is longer than `drop_threshold` (in mesh units) or
// whose normal delta is longer than `normal_drop_threshold`.
// dense_normal_deltas may be empty.
RawBlendShape MakeSparseShape(std::string name, std::span<const glm::vec3> dense_position_deltas,
                              std::span<const glm::vec3> dense_normal_deltas,
                              float drop_threshold, float normal_drop_threshold = 1e-4f);

// Area-weighted vertex normals (unit length; (0,0,1) for isolated vertices).
// `normals` must have positions.size() elements.
void ComputeVertexNormals(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                          std::span<glm::vec3> normals);

class RigBuilder {
 public:
  // Returns the rig, or nullopt when raw.Validate() fails (problem filled in).
  static std::optional<Rig> Build(RawRig raw, std::string* problem = nullptr);
  // The inverse: the rig's data as raw vectors (for editing and re-building).
  static RawRig ToRaw(const Rig& rig);
};

}  // namespace facerig
