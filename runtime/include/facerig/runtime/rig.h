// The immutable runtime rig: a neutral mesh plus named, sparse blend shapes.
//
// Built only by RigBuilder (rig_builder.h) from a validated RawRig, or loaded
// by the readers in io/. Movable, not copyable. Positions are in the mesh's
// own units (see units()), with the up axis given by up_axis().
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/material.h"

namespace facerig {

enum class Units : std::uint8_t { kUnknown = 0, kMillimetres, kCentimetres, kMetres };
enum class UpAxis : std::uint8_t { kY = 0, kZ };

// Metres per unit (1 for kUnknown, which glTF treats as metres).
double MetresPerUnit(Units units);
const char* ToString(Units units);
const char* ToString(UpAxis up);
// Parses "mm", "cm", "m", "unknown" (and long names); nullopt otherwise.
std::optional<Units> ParseUnits(std::string_view text);

using Triangle = std::array<std::uint32_t, 3>;

// A named region of the mesh: a contiguous triangle range, and the span of
// vertex indices those triangles use ([first_vertex, first_vertex + vertex_count)).
// Vertex spans of different parts may overlap when parts share vertices.
struct Part {
  std::string name;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  std::uint32_t first_vertex = 0;
  std::uint32_t vertex_count = 0;
  std::int32_t material = -1;  // index into Rig::materials(); -1: none
};

// A read-only view of one sparse blend shape. vertex_indices is strictly
// increasing; position_deltas[i] applies to vertex vertex_indices[i];
// normal_deltas is either empty (rig without normal deltas) or the same size.
struct BlendShapeView {
  std::string_view name;
  std::span<const std::uint32_t> vertex_indices;
  std::span<const glm::vec3> position_deltas;
  std::span<const glm::vec3> normal_deltas;
};

// Where one shape's entries live in the rig's concatenated shape arrays.
struct ShapeRange {
  std::uint32_t offset = 0;
  std::uint32_t count = 0;
};

class Rig {
 public:
  Rig() = default;
  Rig(Rig&&) noexcept = default;
  Rig& operator=(Rig&&) noexcept = default;
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  std::size_t vertex_count() const { return positions_.size(); }
  std::size_t triangle_count() const { return triangles_.size(); }
  std::size_t shape_count() const { return shape_names_.size(); }

  std::span<const glm::vec3> positions() const { return positions_; }
  // Unit-length, area-weighted vertex normals of the neutral.
  std::span<const glm::vec3> normals() const { return normals_; }
  std::span<const Triangle> triangles() const { return triangles_; }
  // Empty when the rig has no texture coordinates.
  std::span<const glm::vec2> uvs() const { return uvs_; }
  std::span<const Part> parts() const { return parts_; }
  // Empty when the rig has no materials; parts name theirs by index.
  std::span<const Material> materials() const { return materials_; }
  std::span<const EncodedImage> images() const { return images_; }
  Units units() const { return units_; }
  UpAxis up_axis() const { return up_axis_; }
  bool has_normal_deltas() const { return has_normal_deltas_; }

  BlendShapeView shape(std::size_t index) const;
  std::string_view shape_name(std::size_t index) const { return shape_names_[index]; }
  // Index of the shape with this exact name, or nullopt.
  std::optional<std::size_t> FindShape(std::string_view name) const;
  const Part* FindPart(std::string_view name) const;

  // Total sparse entries (vertex, delta) over all shapes.
  std::size_t total_shape_entries() const { return shape_vertex_indices_.size(); }
  // Length of the bounding-box diagonal of the neutral, in the rig's units.
  float bounding_diagonal() const { return bounding_diagonal_; }

  // Raw concatenated storage, for writers that serialise the rig as it is.
  std::span<const ShapeRange> shape_ranges() const { return shape_ranges_; }
  std::span<const std::uint32_t> all_shape_vertex_indices() const { return shape_vertex_indices_; }
  std::span<const glm::vec3> all_shape_position_deltas() const { return shape_position_deltas_; }
  std::span<const glm::vec3> all_shape_normal_deltas() const { return shape_normal_deltas_; }

 private:
  friend class RigBuilder;

  std::vector<glm::vec3> positions_;
  std::vector<glm::vec3> normals_;
  std::vector<Triangle> triangles_;
  std::vector<glm::vec2> uvs_;
  std::vector<Part> parts_;
  std::vector<Material> materials_;
  std::vector<EncodedImage> images_;
  Units units_ = Units::kUnknown;
  UpAxis up_axis_ = UpAxis::kY;
  bool has_normal_deltas_ = false;
  float bounding_diagonal_ = 0.0f;

  std::vector<std::string> shape_names_;
  std::vector<ShapeRange> shape_ranges_;
  std::vector<std::uint32_t> shape_vertex_indices_;
  std::vector<glm::vec3> shape_position_deltas_;
  std::vector<glm::vec3> shape_normal_deltas_;
};

}  // namespace facerig
