// Optimal-step non-rigid ICP (Amberg, Romdhani, Vetter 2007): registers a
// template mesh onto a target surface of any topology with one affine
// transform per template vertex, regularised by a stiffness term that is
// annealed from stiff to soft, guided by landmark pairs and closest-point
// correspondences (with normal-compatibility, boundary and distance rejection).
//
// Units: positions in each mesh's own units; the result is in the target's
// coordinates and units (a similarity alignment from the landmarks, refined
// by ICP, runs first). Stiffness and landmark weights are unitless: the
// problem is solved in a working frame where the template region's bounding
// box diagonal is `working_diagonal`.
//
// The sparse normal equations (4 x #region vertices unknowns, 3 right-hand
// sides) keep one sparsity pattern for the whole run, so the symbolic
// analysis is done once and every iteration only re-factorizes numerically.
#pragma once

#include "facerig/offline/registration/nonrigid_icp_types.h"
#include "facerig/offline/registration/rigid_align.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// \pre template and target are triangle meshes with finite coordinates.
// \throw InvalidInputError on empty meshes, NaN coordinates, landmark
//        indices out of range or mismatched lengths, empty stiffness schedule.
// \throw SolverError when the factorization fails.
NonrigidIcpResult NonrigidIcp(const Mesh& template_mesh, const Mesh& target,
                              const RegistrationLandmarks& landmarks, const NonrigidIcpParams& params = {});

}  // namespace facerig
