#include "facerig/runtime/mesh.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>

namespace facerig {
namespace {

bool Finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

bool SizeIsNoneOr(std::size_t size, std::size_t expected) { return size == 0 || size == expected; }

template <typename T>
std::vector<T> SpreadToCorners(std::span<const T> per_vertex, std::span<const Triangle> triangles) {
  std::vector<T> corners;
  if (per_vertex.empty()) return corners;
  corners.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) corners.push_back(per_vertex[v]);
  }
  return corners;
}

// First corner value per vertex; counts the vertices whose corners disagree.
template <typename T>
std::vector<T> FirstCornerValues(std::span<const T> corners, std::span<const Triangle> triangles,
                                 std::size_t vertex_count, std::size_t& seam_vertices) {
  std::vector<T> values;
  seam_vertices = 0;
  if (corners.empty()) return values;
  values.assign(vertex_count, T(0.0f));
  std::vector<std::uint8_t> state(vertex_count, 0);  // 0 unseen, 1 seen, 2 seam counted
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      const std::uint32_t v = triangles[t][c];
      const T& value = corners[t * 3 + c];
      if (state[v] == 0) {
        values[v] = value;
        state[v] = 1;
      } else if (state[v] == 1 && values[v] != value) {
        state[v] = 2;
        ++seam_vertices;
      }
    }
  }
  return values;
}

std::vector<std::uint32_t> PartRangeIndices(std::span<const RawPart> parts, std::size_t triangle_count,
                                            std::vector<std::string>& names) {
  std::vector<std::uint32_t> triangle_parts;
  if (parts.empty()) return triangle_parts;
  triangle_parts.resize(triangle_count, 0);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    names.push_back(parts[p].name);
    const std::size_t end = std::min<std::size_t>(parts[p].first_triangle + parts[p].triangle_count, triangle_count);
    for (std::size_t t = parts[p].first_triangle; t < end; ++t) triangle_parts[t] = static_cast<std::uint32_t>(p);
  }
  return triangle_parts;
}

// The parts' materials per triangle, when the rig has any; parts without one
// get glTF's default material.
void AddPartMaterials(std::span<const RawPart> parts, std::span<const Material> materials,
                      std::span<const EncodedImage> images, Mesh* mesh) {
  if (materials.empty()) return;
  mesh->materials.assign(materials.begin(), materials.end());
  mesh->images.assign(images.begin(), images.end());
  const auto fallback = static_cast<std::uint32_t>(materials.size());
  bool used_fallback = false;
  mesh->triangle_materials.assign(mesh->triangles.size(), fallback);
  for (const RawPart& part : parts) {
    used_fallback |= part.material < 0;
    const std::uint32_t material = part.material < 0 ? fallback : static_cast<std::uint32_t>(part.material);
    const std::size_t end = std::min<std::size_t>(part.first_triangle + part.triangle_count, mesh->triangles.size());
    for (std::size_t t = part.first_triangle; t < end; ++t) mesh->triangle_materials[t] = material;
  }
  if (used_fallback) mesh->materials.push_back(Material{.name = "default"});
}

}  // namespace

bool Mesh::Validate(std::string* problem) const {
  auto fail = [&](std::string text) {
    if (problem) *problem = std::move(text);
    return false;
  };
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!Finite(positions[v])) return fail("vertex " + std::to_string(v) + ": coordinate is not finite");
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= positions.size()) {
        return fail("triangle " + std::to_string(t) + ": vertex index " + std::to_string(v) +
                    " >= " + std::to_string(positions.size()));
      }
    }
  }
  const std::size_t corners = triangles.size() * 3;
  if (!SizeIsNoneOr(corner_uvs.size(), corners)) return fail("corner UVs: not 3 per triangle");
  if (!SizeIsNoneOr(corner_normals.size(), corners)) return fail("corner normals: not 3 per triangle");
  if (!SizeIsNoneOr(triangle_parts.size(), triangles.size())) return fail("triangle parts: not 1 per triangle");
  if (!SizeIsNoneOr(triangle_materials.size(), triangles.size())) {
    return fail("triangle materials: not 1 per triangle");
  }
  for (std::size_t t = 0; t < triangle_parts.size(); ++t) {
    if (triangle_parts[t] >= part_names.size()) return fail("triangle " + std::to_string(t) + ": part index out of range");
  }
  for (std::size_t t = 0; t < triangle_materials.size(); ++t) {
    if (triangle_materials[t] >= materials.size()) {
      return fail("triangle " + std::to_string(t) + ": material index out of range");
    }
  }
  return ValidateMaterials(materials, images, problem);
}

VertexAttributes PerVertexAttributes(const Mesh& mesh) {
  VertexAttributes attributes;
  attributes.uvs = FirstCornerValues<glm::vec2>(mesh.corner_uvs, mesh.triangles, mesh.vertex_count(),
                                                attributes.uv_seam_vertices);
  attributes.normals = FirstCornerValues<glm::vec3>(mesh.corner_normals, mesh.triangles, mesh.vertex_count(),
                                                    attributes.normal_seam_vertices);
  return attributes;
}

Mesh NeutralMesh(const Rig& rig) {
  Mesh mesh;
  mesh.positions.assign(rig.positions().begin(), rig.positions().end());
  mesh.triangles.assign(rig.triangles().begin(), rig.triangles().end());
  mesh.corner_uvs = SpreadToCorners(rig.uvs(), rig.triangles());
  mesh.corner_normals = SpreadToCorners(rig.normals(), rig.triangles());
  std::vector<RawPart> parts;
  for (const Part& part : rig.parts()) {
    parts.push_back({part.name, part.first_triangle, part.triangle_count, part.material});
  }
  mesh.triangle_parts = PartRangeIndices(parts, mesh.triangles.size(), mesh.part_names);
  AddPartMaterials(parts, rig.materials(), rig.images(), &mesh);
  return mesh;
}

Mesh NeutralMesh(const RawRig& rig) {
  Mesh mesh;
  mesh.positions = rig.positions;
  mesh.triangles = rig.triangles;
  mesh.corner_uvs = SpreadToCorners<glm::vec2>(rig.uvs, rig.triangles);
  mesh.corner_normals = SpreadToCorners<glm::vec3>(rig.normals, rig.triangles);
  mesh.triangle_parts = PartRangeIndices(rig.parts, mesh.triangles.size(), mesh.part_names);
  AddPartMaterials(rig.parts, rig.materials, rig.images, &mesh);
  return mesh;
}

namespace {

// The mesh's triangles in groups of one part and one material: parts in order
// of first appearance, a part's materials likewise, triangles in order within.
std::vector<std::vector<std::uint32_t>> PartMaterialGroups(const Mesh& mesh) {
  const auto material_of = [&](std::size_t t) {
    return mesh.triangle_materials.empty() ? 0u : mesh.triangle_materials[t];
  };
  std::vector<std::vector<std::uint32_t>> groups;
  std::vector<std::vector<std::pair<std::uint32_t, std::size_t>>> part_groups(mesh.part_names.size());
  std::vector<std::uint32_t> part_order;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    auto& of_part = part_groups[mesh.triangle_parts[t]];
    if (of_part.empty()) part_order.push_back(mesh.triangle_parts[t]);
    auto it = std::find_if(of_part.begin(), of_part.end(), [&](const auto& g) { return g.first == material_of(t); });
    if (it == of_part.end()) {
      of_part.emplace_back(material_of(t), groups.size());
      groups.emplace_back();
      it = of_part.end() - 1;
    }
    groups[it->second].push_back(static_cast<std::uint32_t>(t));
  }
  std::vector<std::vector<std::uint32_t>> ordered;
  for (std::uint32_t part : part_order) {
    for (const auto& [material, group] : part_groups[part]) ordered.push_back(std::move(groups[group]));
  }
  return ordered;
}

}  // namespace

Mesh GroupedByPart(const Mesh& mesh) {
  if (mesh.triangle_parts.empty() && mesh.triangle_materials.empty()) return mesh;
  Mesh whole = mesh;
  if (whole.triangle_parts.empty()) {  // one part, split by material below
    whole.part_names = {"mesh"};
    whole.triangle_parts.assign(whole.triangles.size(), 0);
  }
  Mesh grouped{.positions = whole.positions, .part_names = whole.part_names, .materials = whole.materials,
               .images = whole.images};
  grouped.triangles.reserve(whole.triangles.size());
  for (const std::vector<std::uint32_t>& group : PartMaterialGroups(whole)) {
    for (std::uint32_t t : group) {
      grouped.triangles.push_back(whole.triangles[t]);
      grouped.triangle_parts.push_back(whole.triangle_parts[t]);
      if (!whole.triangle_materials.empty()) grouped.triangle_materials.push_back(whole.triangle_materials[t]);
      for (std::size_t c = 0; c < 3; ++c) {
        if (!whole.corner_uvs.empty()) grouped.corner_uvs.push_back(whole.corner_uvs[t * 3 + c]);
        if (!whole.corner_normals.empty()) grouped.corner_normals.push_back(whole.corner_normals[t * 3 + c]);
      }
    }
  }
  return grouped;
}

RawRig ToRawRig(const Mesh& mesh) {
  const Mesh grouped = GroupedByPart(mesh);
  // First corner in the file's order: grouping keeps each vertex's first corner
  // only when its triangles stay in order, so take the attributes before it.
  VertexAttributes attributes = PerVertexAttributes(mesh);
  RawRig raw;
  raw.positions = mesh.positions;
  raw.uvs = std::move(attributes.uvs);
  raw.normals = std::move(attributes.normals);
  raw.triangles = grouped.triangles;
  raw.materials = grouped.materials;
  raw.images = grouped.images;
  if (grouped.triangle_parts.empty()) return raw;
  // Each (part, material) is one range of the grouped triangles.
  const auto material_of = [&](std::size_t t) {
    return grouped.triangle_materials.empty() ? -1 : static_cast<std::int32_t>(grouped.triangle_materials[t]);
  };
  for (std::size_t t = 0; t < grouped.triangles.size(); ++t) {
    const std::uint32_t part = grouped.triangle_parts[t];
    if (t == 0 || part != grouped.triangle_parts[t - 1] || material_of(t) != material_of(t - 1)) {
      raw.parts.push_back({grouped.part_names[part], static_cast<std::uint32_t>(t), 0, material_of(t)});
    }
    ++raw.parts.back().triangle_count;
  }
  return raw;
}

}  // namespace facerig
