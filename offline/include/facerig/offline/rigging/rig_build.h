// Building a rig for a new face, end to end (`facerig build`): landmark pairs
// -> similarity alignment + optimal-step non-rigid ICP of the template onto the
// target -> transfer of every template expression onto the fitted template
// (deformation transfer, classic or identity-gradient, or displacement
// matrices) -> the expressions mapped onto the target's own vertices
// (topology_mapping.h). The result keeps the target's vertex order, UVs,
// parts, units and coordinates, with the template's shape names.
//
// The transfer runs in the template's frame and units (the fitted template
// taken back through the inverse similarity), where the template's static
// anchor set and thresholds are meaningful; the results are moved into the
// target's frame with the similarity (deltas scaled and rotated).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// Each stage's own types only, not its algorithm's header: a caller that
// builds a rig compiles none of the stages' declarations.
#include "facerig/offline/error.h"
#include "facerig/offline/landmarks/face_landmarks.h"
#include "facerig/offline/mapping/topology_mapping_types.h"
#include "facerig/offline/openings/openings.h"
#include "facerig/offline/registration/nonrigid_icp_types.h"
#include "facerig/offline/rigging/build_stages.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/transfer/deformation_transfer_types.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

enum class BuildMode : std::uint8_t {
  kClassic = 0,         // deformation transfer S0 -> Si onto T0
  kIdentityGradient,    // deformation transfer S0 -> T0 onto Si (Pawaskar et al. V.B)
  kDisplacement,        // displacement matrices with bounding-box normalisation (Mattos et al.)
};
const char* ToString(BuildMode mode);
// "classic", "identity", "displacement"; nullopt otherwise.
std::optional<BuildMode> ParseBuildMode(std::string_view text);

struct BuildRigParams {
  BuildMode mode = BuildMode::kClassic;
  // region_vertex_count 0: the template descriptor's region. `progress` is
  // replaced by the one below.
  NonrigidIcpParams registration;
  // `mode` is set from `mode` above, `openings` from `openings` below.
  DeformationTransferParams transfer;
  TopologyMappingParams mapping;  // `openings` is set from `openings` below
  // The eyelids and lips: contacts, margin alignment, the target's rims.
  OpeningParams openings;
  // A fit whose mean residual exceeds this (% of the target's diagonal) is a
  // mismatch: RegistrationMismatchError. Good fits measure ~0.01 %.
  double max_residual_mean_percent = 1.0;
  // A fit that had to move the template's surface further than this from its
  // rigidly aligned shape (mean, % of the template region's diagonal) is a
  // mismatch too: a face registered onto a sheet or a box fits closely but
  // only by collapsing. Random ICT identities measure ~0.5 %.
  double max_deformation_percent = 10.0;
  // The template is registered onto the target's connected parts whose area
  // is at least this fraction of the largest part's (the skin; not separate
  // eyeballs, teeth or lashes, which the template has parts of its own for).
  double registration_min_part_area = 0.1;
  // Before the transfer, move the fitted template's lid margins (vertices
  // that meet across an opening in one of its expressions) onto the target's
  // rims where the target's openings are holes (openings.h): the
  // registration fits surfaces, not rims, and a margin left a millimetre off
  // made the stylized head's blink stop short.
  bool align_margins_to_openings = true;
  // A template without tongueOut but with a tongue part (ICT-FaceKit) gets
  // one made from its tongue before the transfer (tongue_out.h), unless the
  // target has a tongueOut of its own, which it keeps.
  bool synthesise_tongue_out = true;
  // The one progress report of the build: called with the stage's name (the
  // names of BuildRigResult::stages) and its progress (done of total).
  std::function<void(const char* stage, std::size_t done, std::size_t total)> progress;
};

struct BuildRigTimings {
  double registration_seconds = 0.0;
  double transfer_seconds = 0.0;  // including the margin alignment and the transfer's precompute
  double margin_seconds = 0.0;
  double transfer_precompute_seconds = 0.0;  // deformation transfer: including its factorization
  double transfer_solve_seconds = 0.0;  // deformation transfer: all expressions
  double mapping_seconds = 0.0;
  double total_seconds = 0.0;
};


// A build's target as loaded (LoadBuildTarget, offline/io/build_target.h):
// the rig data the stages work on, and its mesh as the file has it (corner
// UVs and normals, parts, materials) on the rig's vertices, triangle t being
// the rig's triangle t, for the writers.
struct BuildTarget {
  RawRig rig;
  Mesh mesh;
};

struct BuildRigResult {
  RawRig rig;         // on the target's topology, frame and units
  // BuildRig of a BuildTarget: its mesh, the surface of `rig` (same vertices
  // and triangles) with the file's UVs, parts and materials; else empty.
  Mesh target_mesh;
  RawRig fitted_rig;  // the template's topology in the target's frame and units
  // The same in the template's frame and units (the similarity undone): fits
  // of several faces are comparable (AverageFace, Caricature, IdentityMorphRig).
  RawRig template_frame_rig;
  NonrigidIcpResult registration;
  TopologyMapping mapping;
  std::size_t transfer_anchors = 0;  // deformation transfer: anchored vertices
  // Deformation transfer: whether contacts acted (DeformationTransferResult::
  // contacts_active; false in displacement mode), and the pairs kept over all expressions.
  bool transfer_contacts_active = false;
  std::size_t transfer_contacts = 0;
  std::size_t target_parts_left_out = 0;  // small target parts not registered onto (BuildRig)
  // align_margins_to_openings: template margin vertices moved onto a target
  // rim, and their mean move (target units).
  std::size_t margin_vertices_aligned = 0;
  double margin_mean_correction = 0.0;
  // How far the fit moved the template's region from its rigidly aligned
  // shape: mean distance, % of the region's diagonal.
  double deformation_percent = 0.0;
  // The template part tongueOut was synthesised from; empty when the
  // template had its own or no tongue.
  std::string tongue_out_synthesised_from;
  BuildRigTimings timings;
  // Every stage in order: "register", "align margins", "to template frame",
  // "transfer", "to target frame", "map" (BuildRigOnRegistration: the same
  // without "register").
  std::vector<BuildStage> stages;
};

// target: the user's mesh (positions, triangles, UVs, parts, units) as read by LoadRig.
// landmarks: template vertex <-> target point pairs (PairLandmarks).
// The template's descriptor gives the registered region and the rims.
// \throw InvalidInputError, SolverError, MeshInputError, TransferSolverError,
//        RegistrationMismatchError.
BuildRigResult BuildRig(const Rig& template_rig, const FaceTemplateInfo& template_info, RawRig target,
                        const RegistrationLandmarks& landmarks, const BuildRigParams& params = {});

// The same for a target as loaded: result.target_mesh is target.mesh.
BuildRigResult BuildRig(const Rig& template_rig, const FaceTemplateInfo& template_info, BuildTarget target,
                        const RegistrationLandmarks& landmarks, const BuildRigParams& params = {});

// The same from an existing registration of the template onto target (e.g.
// to compare modes without registering again).
BuildRigResult BuildRigOnRegistration(const Rig& template_rig, const FaceTemplateInfo& template_info, RawRig target,
                                      NonrigidIcpResult registered, const BuildRigParams& params = {});

// Pairs detected (or read) target landmarks with template vertices.
// \throw InvalidInputError when a landmark index is not below template_vertex_of.size().
RegistrationLandmarks PairLandmarks(const std::vector<std::uint32_t>& template_vertex_of,
                                    const FaceLandmarks& target_landmarks);

}  // namespace facerig
