#include "facerig/offline/identity/caricature.h"

#include <cmath>

#include "facerig/offline/transfer/displacement_transfer.h"

namespace facerig {

std::vector<glm::vec3> AverageFace(std::span<const std::vector<glm::vec3>> faces, bool align) {
  if (faces.empty()) throw MeshInputError("faces", "no faces to average");
  const std::size_t n = faces[0].size();
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (faces[f].size() != n) {
      throw MeshInputError("face " + std::to_string(f),
                               "has " + std::to_string(faces[f].size()) + " vertices, expected " +
                                   std::to_string(n));
    }
    SimilarityTransform transform;
    if (align && f > 0 && n >= 3) transform = FitRigid(faces[f], faces[0]);
    for (std::size_t v = 0; v < n; ++v) sum[v] += glm::dvec3(transform.Apply(faces[f][v]));
  }
  std::vector<glm::vec3> average(n);
  const double scale = 1.0 / static_cast<double>(faces.size());
  for (std::size_t v = 0; v < n; ++v) average[v] = glm::vec3(sum[v] * scale);
  return average;
}

std::vector<glm::vec3> Caricature(std::span<const glm::vec3> face, std::span<const glm::vec3> average,
                                  float factor) {
  if (!(factor >= kMinCaricatureFactor && factor <= kMaxCaricatureFactor)) {
    throw MeshInputError("caricature factor",
                             std::to_string(factor) + " is outside [-1, 3]");
  }
  if (average.size() != face.size()) {
    throw MeshInputError("average face", "has " + std::to_string(average.size()) +
                                                 " vertices, the face " + std::to_string(face.size()));
  }
  std::vector<glm::vec3> result(face.size());
  for (std::size_t v = 0; v < face.size(); ++v) {
    result[v] = face[v] + factor * (face[v] - average[v]);
  }
  return result;
}

RawRig CaricatureRig(const Rig& rig, std::span<const glm::vec3> average,
                     const CaricatureParams& params) {
  const std::vector<glm::vec3> neutral = Caricature(rig.positions(), average, params.factor);
  if (params.expressions == CaricatureExpressions::kDeformationTransfer) {
    return TransferRig(rig, neutral, params.transfer);
  }
  RawRig raw = RigBuilder::ToRaw(rig);
  raw.positions = neutral;
  raw.normals.clear();
  if (rig.has_normal_deltas()) {
    // Normal deltas belong to the old surface; drop them rather than keep stale ones.
    for (RawBlendShape& shape : raw.shapes) shape.normal_deltas.clear();
  }
  return raw;
}

RawRig IdentityMorphRig(const Rig& template_rig, const Rig& target_rig) {
  if (target_rig.vertex_count() != template_rig.vertex_count()) {
    throw MeshInputError("target rig", "has " + std::to_string(target_rig.vertex_count()) +
                                               " vertices, the template " +
                                               std::to_string(template_rig.vertex_count()));
  }
  if (target_rig.triangle_count() != template_rig.triangle_count()) {
    throw MeshInputError("target rig", "has a different triangle count from the template");
  }
  if (target_rig.FindShape(kIdentityMorphShape)) {
    throw MeshInputError("target rig", "already has a shape called identityMorph");
  }
  RawRig raw = RigBuilder::ToRaw(target_rig);
  const std::span<const glm::vec3> from = template_rig.positions();
  const std::span<const glm::vec3> to = target_rig.positions();
  std::vector<glm::vec3> deltas(from.size());
  for (std::size_t v = 0; v < from.size(); ++v) deltas[v] = to[v] - from[v];
  raw.positions.assign(from.begin(), from.end());
  raw.normals.clear();
  const float threshold = 1e-6f * target_rig.bounding_diagonal();
  RawBlendShape morph = MakeSparseShape(kIdentityMorphShape, deltas, {}, threshold);
  if (target_rig.has_normal_deltas()) {
    // Every shape needs normal deltas when one has: the neutral normals' change.
    std::vector<glm::vec3> from_normals(from.size());
    ComputeVertexNormals(from, raw.triangles, from_normals);
    std::vector<glm::vec3> normal_deltas(from.size());
    for (std::size_t v = 0; v < from.size(); ++v) {
      normal_deltas[v] = target_rig.normals()[v] - from_normals[v];
    }
    morph = MakeSparseShape(kIdentityMorphShape, deltas, normal_deltas, threshold);
  }
  raw.shapes.push_back(std::move(morph));
  return raw;
}

}  // namespace facerig
