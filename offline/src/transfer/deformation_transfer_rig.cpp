#include "transfer/deformation_transfer_impl.h"

#include <algorithm>

#include "geometry/parallel_for.h"

namespace facerig {

DeformationTransferResult DeformationTransfer(const Mesh& source, std::span<const glm::vec3> target_neutral,
                                              std::span<const std::vector<glm::vec3>> source_expressions,
                                              const DeformationTransferParams& params) {
  if (params.threads < 1) throw MeshInputError("params", "threads must be >= 1");
  DeformationTransferData data;
  PrecomputeDeformationTransfer(source, target_neutral, source_expressions, params, data);
  DeformationTransferResult result;
  result.anchor_count = data.anchor_count;
  result.floating_components = data.floating_components;
  result.regularized_triangles = data.regularized_triangles;
  result.contacts_active = data.contacts_active;
  result.precompute_seconds = data.precompute_seconds;
  result.factorize_seconds = data.factorize_seconds;

  const Clock::time_point start = Clock::now();
  const std::size_t count = source_expressions.size();
  result.expressions.resize(count);
  result.residuals.assign(count, 0.0);
  result.contact_counts.assign(count, 0);
  const DeformationTransferData::Impl& impl = *data.impl;
  // One expression at a time to the next free thread (their costs differ:
  // the jaw's solve is the largest).
  using Scratch = DeformationTransferData::Impl::Scratch;
  const auto solve = [&](Scratch& scratch, std::size_t k) {
    result.residuals[k] = impl.Solve(source_expressions[k], result.expressions[k], scratch);
    result.contact_counts[k] = scratch.contacts.size();
  };
  ParallelForWithState<Scratch>(count, 1, static_cast<std::size_t>(params.threads), solve);
  result.solve_seconds = SecondsSince(start);
  return result;
}

std::vector<std::vector<glm::vec3>> RigExpressionMeshes(const Rig& rig) {
  std::vector<std::vector<glm::vec3>> meshes(rig.shape_count());
  const std::span<const glm::vec3> neutral = rig.positions();
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    meshes[s].assign(neutral.begin(), neutral.end());
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      meshes[s][shape.vertex_indices[i]] += shape.position_deltas[i];
    }
  }
  return meshes;
}

std::vector<RawBlendShape> MakeBlendShapes(std::span<const std::string> names,
                                           std::span<const glm::vec3> neutral,
                                           std::span<const std::vector<glm::vec3>> expressions,
                                           float relative_drop_threshold) {
  if (names.size() != expressions.size()) {
    throw MeshInputError("shape names", std::to_string(names.size()) + " names for " +
                                                std::to_string(expressions.size()) + " expressions");
  }
  const float threshold = relative_drop_threshold * BoundingDiagonal(neutral);
  std::vector<RawBlendShape> shapes;
  shapes.reserve(expressions.size());
  std::vector<glm::vec3> deltas(neutral.size());
  for (std::size_t s = 0; s < expressions.size(); ++s) {
    CheckPositions(expressions[s], neutral.size(), "expression '" + names[s] + "'");
    for (std::size_t v = 0; v < neutral.size(); ++v) deltas[v] = expressions[s][v] - neutral[v];
    shapes.push_back(MakeSparseShape(names[s], deltas, {}, threshold));
  }
  return shapes;
}

RawRig TransferRig(const Rig& template_rig, std::span<const glm::vec3> target_neutral,
                   const DeformationTransferParams& params, DeformationTransferResult* result) {
  CheckPositions(target_neutral, template_rig.vertex_count(), "target neutral");
  const std::vector<std::vector<glm::vec3>> expressions = RigExpressionMeshes(template_rig);
  DeformationTransferResult transfer =
      DeformationTransfer(NeutralMesh(template_rig), target_neutral, expressions, params);
  RawRig raw = RigBuilder::ToRaw(template_rig);
  raw.positions.assign(target_neutral.begin(), target_neutral.end());
  raw.normals.clear();
  std::vector<std::string> names;
  for (std::size_t s = 0; s < template_rig.shape_count(); ++s) {
    names.emplace_back(template_rig.shape_name(s));
  }
  raw.shapes = MakeBlendShapes(names, target_neutral, transfer.expressions);
  if (template_rig.has_normal_deltas()) {
    // Keep the rig's kind: normal deltas from the transferred meshes.
    std::vector<glm::vec3> neutral_normals(target_neutral.size());
    std::vector<glm::vec3> normals(target_neutral.size());
    ComputeVertexNormals(target_neutral, raw.triangles, neutral_normals);
    const float threshold = 1e-6f * BoundingDiagonal(target_neutral);
    std::vector<glm::vec3> deltas(target_neutral.size());
    for (std::size_t s = 0; s < raw.shapes.size(); ++s) {
      ComputeVertexNormals(transfer.expressions[s], raw.triangles, normals);
      for (std::size_t v = 0; v < normals.size(); ++v) {
        deltas[v] = transfer.expressions[s][v] - target_neutral[v];
        normals[v] -= neutral_normals[v];
      }
      raw.shapes[s] = MakeSparseShape(names[s], deltas, normals, threshold);
    }
  }
  if (result) *result = std::move(transfer);
  return raw;
}

}  // namespace facerig
