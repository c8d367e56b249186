// Displacement matrices (Mattos, Cesar, Mena-Chalco & Velho, "3D Linear
// Facial Animation Based on Real Data"): per pose k the n x 3 matrix
// M^k of vertex displacements from the neutral, after rigid alignment of the
// pose onto the neutral; transfer to another face in per-vertex
// correspondence with bounding-box normalisation (eq. 4-6); combining poses;
// a binary file format. The simple baseline to compare deformation transfer
// with on the same face.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "facerig/offline/geometry/similarity.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// p' = rotation * p + translation.
struct DisplacementMatrices {
  std::vector<std::string> names;                   // one per pose
  std::vector<std::vector<glm::vec3>> displacements;  // per pose, #V (the matrix M^k)
  glm::vec3 base_extent{0.0f};                      // bounding-box size of the base neutral (X, Y, Z)
  std::size_t vertex_count = 0;
};

struct DisplacementParams {
  // Rigidly align each pose onto the neutral before differencing (scans move
  // between takes). Aligned over `alignment_vertices`, or, when
  // empty, over the half of the vertices the pose moves least (the head, not
  // the jaw, defines the pose's frame).
  bool rigid_align = true;
  std::vector<std::uint32_t> alignment_vertices;
};

// neutral: #V; poses: each #V. \throw MeshInputError naming the pose.
DisplacementMatrices ComputeDisplacementMatrices(std::span<const glm::vec3> neutral,
                                                 std::span<const std::vector<glm::vec3>> poses,
                                                 std::span<const std::string> names,
                                                 const DisplacementParams& params = {});
// The rig's shapes as poses (already aligned: no alignment).
DisplacementMatrices ComputeDisplacementMatrices(const Rig& rig);

struct DisplacementTransferParams {
  // Scale each axis by the bounding-box ratio model / base (eq. 4-6).
  bool normalize_by_bounding_box = true;
  // Vertices whose bounding box is compared (empty: all), e.g. the face region.
  std::vector<std::uint32_t> bounding_box_vertices;
  // The base neutral the matrices were computed on (#V), optional: needed for
  // bounding_box_vertices (the base's box over the same vertices) and for align_model.
  std::vector<glm::vec3> base_neutral;
  // With base_neutral: rigidly align the model onto it first, compare the
  // boxes in the base's frame and rotate the displacements into the model's
  // frame (the model may be posed differently).
  bool align_model = true;
};

struct DisplacementTransferResult {
  std::vector<std::vector<glm::vec3>> poses;  // per pose, #V model positions
  glm::vec3 scale{1.0f};                      // per-axis factor applied (base frame)
  SimilarityTransform model_to_base;  // rigid (scale 1)
  double model_to_base_rms = 0.0;     // its residual, base units
  double seconds = 0.0;
};

// The base's poses on `model_neutral` (same vertex count, corresponded).
// \throw MeshInputError on size mismatch or an empty bounding box.
DisplacementTransferResult TransferDisplacements(const DisplacementMatrices& matrices,
                                                 std::span<const glm::vec3> model_neutral,
                                                 const DisplacementTransferParams& params = {});

// sum_k weights[k] * M^k (#V): several poses combined into one expression.
// \throw MeshInputError when weights.size() != pose count.
std::vector<glm::vec3> CombinePoses(const DisplacementMatrices& matrices,
                                    std::span<const float> weights);

// File format (.fdm, little-endian binary), version 1:
//   char[4]  magic "FDM1"
//   u32      version (1)
//   u32      vertex_count N, u32 pose_count K
//   f32[3]   base_extent
//   K times: u32 name length L (<= 4096), L bytes UTF-8 name, f32[3N] displacements (x y z per vertex)
//   u32      FNV-1a hash of every byte before it
// Atomic write (temporary file + rename). \throw IoError (kWriteFailed).
void WriteDisplacementMatrices(const std::filesystem::path& path,
                               const DisplacementMatrices& matrices);
// \throw IoError: kOpenFailed, kBadMagic, kUnsupportedVersion, kTruncated,
// kAbsurdCount, kNonFinite, kChecksumMismatch, kParse (trailing bytes).
DisplacementMatrices ReadDisplacementMatrices(const std::filesystem::path& path);

}  // namespace facerig
