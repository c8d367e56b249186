// Average face and caricature (Mattos, Cesar, Mena-Chalco & Velho, "3D Linear
// Facial Animation Based on Real Data"), and the identity morph of Pawaskar,
// Ma, Carnegie, Lewis & Rhee ("Expression Transfer: A System to Build 3D Blend
// Shapes for Facial Animation"). Faces here are in per-vertex correspondence
// (same topology: the template, or templates fitted to scans).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "facerig/offline/transfer/deformation_transfer.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

// Mean position of every vertex over `faces` (each #V). With `align`, every
// face is first rigidly aligned (Kabsch over all vertices) onto the first, so
// head pose does not blur the average. \throw MeshInputError on an empty
// list or mismatched vertex counts (naming the face).
std::vector<glm::vec3> AverageFace(std::span<const std::vector<glm::vec3>> faces, bool align = true);

// The caricature limits: factor -1 gives the average, 0 the face itself, 3
// four times the face's difference from the average.
inline constexpr float kMinCaricatureFactor = -1.0f;
inline constexpr float kMaxCaricatureFactor = 3.0f;

// face + factor * (face - average), per vertex (the face and the average in the
// same frame). \throw MeshInputError for a factor outside [-1, 3] or mismatched sizes.
std::vector<glm::vec3> Caricature(std::span<const glm::vec3> face, std::span<const glm::vec3> average,
                                  float factor);

enum class CaricatureExpressions : std::uint8_t {
  // Re-derive the expressions on the caricatured neutral by deformation
  // transfer from the face's own rig (a wider mouth opens wider).
  kDeformationTransfer = 0,
  // Keep the face's expression deltas unchanged.
  kKeepDeltas,
};

struct CaricatureParams {
  float factor = 1.0f;  // in [-1, 3], see Caricature()
  CaricatureExpressions expressions = CaricatureExpressions::kDeformationTransfer;
  DeformationTransferParams transfer;  // for kDeformationTransfer
};

// A copy of `rig` whose neutral is caricatured against `average` (#V, same
// frame as the rig) and whose expressions follow consistently.
// \throw MeshInputError, TransferSolverError.
RawRig CaricatureRig(const Rig& rig, std::span<const glm::vec3> average,
                     const CaricatureParams& params = {});

// Name of the identity control added by IdentityMorphRig.
inline constexpr const char* kIdentityMorphShape = "identityMorph";

// Identity morph (Pawaskar et al.): a rig with the template's neutral, the target's expression
// shapes (target_rig's, e.g. from TransferRig) and one more control shape
// "identityMorph" = target neutral - template neutral. identityMorph at 0 is
// the template's face, at 1 exactly target_rig; the expressions work at any
// identity weight (linear blend shapes: the expression deltas are the
// target's at every identity weight).
// \pre same vertex count and triangles; \throw MeshInputError otherwise or
// when a shape is already called "identityMorph".
RawRig IdentityMorphRig(const Rig& template_rig, const Rig& target_rig);

}  // namespace facerig
