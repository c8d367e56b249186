// Parts of a face that cannot bend (teeth, eyeballs) move as rigid bodies in
// every shape a build maps onto a target. The mapping takes each vertex's
// motion from the nearest template surface; where the target's teeth do not
// sit where the fitted template's do, some of an upper row's vertices find
// the template's lower gums and follow the jaw, and the row tears.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig_builder.h"

namespace facerig {

// The connected pieces (vertex lists) of the target's parts whose role is
// rigid: teeth, sclera, iris, pupil (part_roles.h). A piece of fewer than
// three vertices is left out.
std::vector<std::vector<std::uint32_t>> RigidPieces(const RawRig& rig);

// Replaces each piece's deltas by the rigid motion that most of its vertices
// agree on: a least-squares rigid fit, reweighted so that vertices far from
// the fit (the few that found the wrong surface) stop counting.
void MoveRigidPiecesRigidly(std::span<const std::vector<std::uint32_t>> pieces, std::span<const glm::vec3> positions,
                            std::span<glm::vec3> deltas);

}  // namespace facerig
