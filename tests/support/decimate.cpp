#include "support/decimate.h"

#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <meshoptimizer.h>

namespace facerig::test {
namespace {

using GroupKey = std::pair<std::uint32_t, std::uint32_t>;  // part, material

GroupKey GroupOf(const Mesh& mesh, std::size_t triangle) {
  return {mesh.triangle_parts.empty() ? 0u : mesh.triangle_parts[triangle],
          mesh.triangle_materials.empty() ? 0u : mesh.triangle_materials[triangle]};
}

// The group's triangles simplified, as flat original vertex indices.
std::vector<std::uint32_t> SimplifyGroup(const Mesh& mesh, const std::vector<std::uint32_t>& indices,
                                         double triangle_fraction) {
  const std::size_t target = 3 * static_cast<std::size_t>(triangle_fraction * static_cast<double>(indices.size() / 3));
  std::vector<std::uint32_t> simplified(indices.size());
  // No error bound: the triangle count decides, as a decimation tool's target count does.
  const std::size_t count = meshopt_simplify(simplified.data(), indices.data(), indices.size(),
                                             &mesh.positions[0].x, mesh.positions.size(), sizeof(glm::vec3), target,
                                             std::numeric_limits<float>::max(), meshopt_SimplifyLockBorder, nullptr);
  simplified.resize(count);
  return simplified;
}

}  // namespace

DecimatedMesh Decimate(const Mesh& mesh, double triangle_fraction) {
  std::string problem;
  if (!(triangle_fraction > 0.0 && triangle_fraction <= 1.0)) throw std::invalid_argument("Decimate: fraction");
  if (!mesh.Validate(&problem)) throw std::invalid_argument("Decimate: " + problem);
  std::map<GroupKey, std::vector<std::uint32_t>> groups;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::vector<std::uint32_t>& indices = groups[GroupOf(mesh, t)];
    indices.insert(indices.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
  }
  DecimatedMesh result;
  result.mesh.part_names = mesh.part_names;
  result.mesh.materials = mesh.materials;
  result.mesh.images = mesh.images;
  constexpr std::uint32_t kDropped = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> new_index(mesh.positions.size(), kDropped);
  for (const auto& [key, indices] : groups) {
    const std::vector<std::uint32_t> simplified = SimplifyGroup(mesh, indices, triangle_fraction);
    for (std::size_t i = 0; i < simplified.size(); i += 3) {
      result.mesh.triangles.push_back({simplified[i], simplified[i + 1], simplified[i + 2]});
      if (!mesh.triangle_parts.empty()) result.mesh.triangle_parts.push_back(key.first);
      if (!mesh.triangle_materials.empty()) result.mesh.triangle_materials.push_back(key.second);
      for (std::size_t c = 0; c < 3; ++c) new_index[simplified[i + c]] = 0;
    }
  }
  // Kept vertices in their original order.
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    if (new_index[v] == kDropped) continue;
    new_index[v] = static_cast<std::uint32_t>(result.original_vertex.size());
    result.original_vertex.push_back(v);
    result.mesh.positions.push_back(mesh.positions[v]);
  }
  for (Triangle& triangle : result.mesh.triangles) {
    for (std::uint32_t& v : triangle) v = new_index[v];
  }
  return result;
}

}  // namespace facerig::test
