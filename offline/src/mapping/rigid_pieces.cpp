#include "facerig/offline/mapping/rigid_pieces.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/similarity.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/part_roles.h"

namespace facerig {

namespace {

bool IsRigidRole(PartRole role) {
  return role == PartRole::kTeeth || role == PartRole::kSclera || role == PartRole::kIris ||
         role == PartRole::kPupil;
}

// Where most of the piece goes: the component-wise median displacement (no
// rotation), the start of the reweighting.
SimilarityTransform MedianTranslation(std::span<const std::uint32_t> piece, std::span<const glm::vec3> deltas) {
  SimilarityTransform start;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> values;
    values.reserve(piece.size());
    for (const std::uint32_t v : piece) values.push_back(deltas[v][axis]);
    start.translation[axis] = Median(std::move(values));
  }
  return start;
}

// Tukey's biweight on the residuals, scaled by their median absolute size.
std::vector<float> BiweightWeights(std::span<const float> residuals, float floor) {
  const float scale = std::max(1.4826f * Median({residuals.begin(), residuals.end()}), floor);
  const float cutoff = 4.685f * scale;
  std::vector<float> weights(residuals.size());
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const float u = residuals[i] / cutoff;
    weights[i] = u < 1.0f ? (1.0f - u * u) * (1.0f - u * u) : 0.0f;
  }
  return weights;
}

SimilarityTransform RobustRigidMotion(std::span<const std::uint32_t> piece, std::span<const glm::vec3> positions,
                                      std::span<const glm::vec3> deltas) {
  std::vector<glm::vec3> rest, moved;
  float extent = 0.0f;
  for (const std::uint32_t v : piece) {
    rest.push_back(positions[v]);
    moved.push_back(positions[v] + deltas[v]);
    extent = std::max(extent, glm::length(positions[v] - positions[piece.front()]));
  }
  SimilarityTransform motion = MedianTranslation(piece, deltas);
  std::vector<float> residuals(piece.size());
  for (int round = 0; round < 5; ++round) {
    for (std::size_t i = 0; i < piece.size(); ++i) residuals[i] = glm::length(motion.Apply(rest[i]) - moved[i]);
    const std::vector<float> weights = BiweightWeights(residuals, 1e-4f * extent);
    try {
      motion = Umeyama(rest, moved, weights, false);
    } catch (const InvalidInputError&) {
      break;  // fewer than three vertices agree: keep the last motion
    }
  }
  return motion;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> RigidPieces(const RawRig& rig) {
  std::vector<std::uint32_t> component;
  ConnectedComponents(rig.positions.size(), rig.triangles, component);
  std::map<std::uint32_t, std::vector<std::uint32_t>> by_component;
  std::vector<std::uint8_t> taken(rig.positions.size(), 0);
  for (const RawPart& part : rig.parts) {
    if (!IsRigidRole(RoleOfPart(part.name))) continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (const std::uint32_t v : rig.triangles[t]) {
        if (taken[v]) continue;
        taken[v] = 1;
        by_component[component[v]].push_back(v);
      }
    }
  }
  std::vector<std::vector<std::uint32_t>> pieces;
  for (auto& [id, vertices] : by_component) {
    if (vertices.size() >= 3) pieces.push_back(std::move(vertices));
  }
  return pieces;
}

void MoveRigidPiecesRigidly(std::span<const std::vector<std::uint32_t>> pieces, std::span<const glm::vec3> positions,
                            std::span<glm::vec3> deltas) {
  for (const std::vector<std::uint32_t>& piece : pieces) {
    const bool still = std::all_of(piece.begin(), piece.end(), [&](std::uint32_t v) { return deltas[v] == glm::vec3(0.0f); });
    if (still) continue;
    const SimilarityTransform motion = RobustRigidMotion(piece, positions, deltas);
    for (const std::uint32_t v : piece) deltas[v] = motion.Apply(positions[v]) - positions[v];
  }
}

}  // namespace facerig
