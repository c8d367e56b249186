// Rigid (similarity) alignment of a source mesh onto a target mesh: Umeyama's
// closed form from landmark pairs, refined by point-to-plane ICP with outlier
// rejection. Scale is estimated, so metres vs centimetres (ratio 100) works.
//
// Positions in each mesh's own units; the transform maps source coordinates
// to target coordinates: x_target = scale * rotation * x_source + translation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <glm/vec3.hpp>

#include "facerig/offline/geometry/similarity.h"
#include "facerig/offline/registration/rigid_align_types.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

class ClosestPointQuery;

// Aligns the source mesh onto the target. With >= 3 landmark pairs
// (source_landmarks[i] on the source <-> target_landmarks[i] on the target)
// the start is their Umeyama transform, else `initial` when given, else the
// centroids and RMS radii of the vertex sets (no rotation).
// \throw InvalidInputError on empty meshes, NaN coordinates, mismatched
//        landmark counts.
RigidAlignResult RigidAlign(const Mesh& source, const Mesh& target,
                            std::span<const glm::vec3> source_landmarks = {},
                            std::span<const glm::vec3> target_landmarks = {},
                            const RigidAlignParams& params = {},
                            const SimilarityTransform* initial = nullptr);

// The same with a prebuilt closest-point structure of the target.
RigidAlignResult RigidAlign(const Mesh& source, const ClosestPointQuery& target,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial);

// Checks positions for non-finite values and triangles for indices out of
// range. \throw InvalidInputError naming `what` and the vertex/triangle.
void CheckMesh(const Mesh& mesh, const char* what);

}  // namespace facerig
