#include "facerig/offline/openings/margins.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/offline/rigging/template_preparation.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string_view>


#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/transfer/deformation_transfer.h"
#include "facerig/offline/transfer/displacement_transfer.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "facerig/offline/mapping/mouth_sides.h"
#include "facerig/offline/mapping/topology_mapping.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/offline/geometry/stats.h"
#include "geometry/bounding_box.h"

namespace facerig {
namespace {

// Units of a target whose file does not say: the template's units divided by
// the registration's scale, rounded to mm / cm / m in log scale (a head is a
// head: scale 0.01 from a centimetre template means metres).
Units InferTargetUnits(Units template_units, double scale) {
  if (template_units == Units::kUnknown || !(scale > 0.0)) return Units::kUnknown;
  const double target_metres_per_unit = MetresPerUnit(template_units) / scale;
  Units best = Units::kUnknown;
  double best_distance = std::numeric_limits<double>::infinity();
  for (Units units : {Units::kMillimetres, Units::kCentimetres, Units::kMetres}) {
    const double distance = std::abs(std::log10(target_metres_per_unit / MetresPerUnit(units)));
    if (distance < best_distance) {
      best_distance = distance;
      best = units;
    }
  }
  return best_distance < 0.5 ? best : Units::kUnknown;  // within a factor ~3 of a unit
}

// The template's expressions on `fitted` (template frame, template topology),
// as sparse shapes, by the chosen method; the deformation transfer's anchor
// and contact counts into built.
std::vector<RawBlendShape> TransferExpressions(const Rig& template_rig, std::span<const glm::vec3> fitted,
                                               std::uint32_t region_vertex_count, const BuildRigParams& params,
                                               BuildRigResult& built) {
  if (params.mode == BuildMode::kDisplacement) {
    const DisplacementMatrices matrices = ComputeDisplacementMatrices(template_rig);
    DisplacementTransferParams displacement;
    displacement.base_neutral.assign(template_rig.positions().begin(), template_rig.positions().end());
    displacement.bounding_box_vertices.resize(region_vertex_count);
    std::iota(displacement.bounding_box_vertices.begin(), displacement.bounding_box_vertices.end(), 0u);
    const DisplacementTransferResult result = TransferDisplacements(matrices, fitted, displacement);
    return MakeBlendShapes(matrices.names, fitted, result.poses);
  }
  DeformationTransferParams transfer = params.transfer;
  transfer.mode = params.mode == BuildMode::kClassic ? TransferMode::kClassic : TransferMode::kIdentityGradient;
  transfer.openings = params.openings;
  DeformationTransferResult result;
  RawRig transferred = TransferRig(template_rig, fitted, transfer, &result);
  built.transfer_anchors = result.anchor_count;
  built.transfer_contacts_active = result.contacts_active;
  built.timings.transfer_precompute_seconds = result.precompute_seconds;
  built.timings.transfer_solve_seconds = result.solve_seconds;
  built.transfer_contacts =
      std::accumulate(result.contact_counts.begin(), result.contact_counts.end(), std::size_t{0});
  return std::move(transferred.shapes);
}

// Mean distance between the template's region and its fitted shape (both in
// the template's frame), as a percentage of the region's bounding-box diagonal.
double MeanDeformationPercent(std::span<const glm::vec3> template_positions, std::span<const glm::vec3> fitted,
                              std::uint32_t region_vertex_count) {
  double sum = 0.0;
  for (std::uint32_t v = 0; v < region_vertex_count; ++v) sum += glm::length(fitted[v] - template_positions[v]);
  const double diagonal = BoxAround(template_positions.first(region_vertex_count)).diagonal();
  return region_vertex_count > 0 && diagonal > 0.0 ? 100.0 * sum / region_vertex_count / diagonal : 0.0;
}

// Runs the build's stages: reports each through BuildRigParams::progress and
// records its time in BuildRigResult::stages.
class StageRunner {
 public:
  StageRunner(const BuildRigParams& params, BuildRigResult& result) : params_(params), result_(result) {}

  template <typename Body>
  auto Run(const char* name, Body&& body) {
    if (params_.progress) params_.progress(name, 0, 1);
    auto value = TimeStage(result_.stages, name, std::forward<Body>(body));
    if (params_.progress) params_.progress(name, 1, 1);
    return value;
  }

  double SecondsOf(std::string_view name) const { return StageSeconds(result_.stages, name); }

 private:
  const BuildRigParams& params_;
  BuildRigResult& result_;
};

void CheckResidual(const ResidualStats& residual, const BuildRigParams& params) {
  if (residual.mean_percent <= params.max_residual_mean_percent) return;
  throw RegistrationMismatchError(
      "the template does not match the target: registration residual mean " + std::to_string(residual.mean_percent) +
      " % of the target's diagonal (p95 " + std::to_string(residual.p95_percent) + " %, limit " +
      std::to_string(params.max_residual_mean_percent) + " %); is the target a face, and are the landmarks right?");
}

struct MarginStage {
  std::vector<OpeningMargin> margins;
  MarginAlignmentResult aligned;
};

// The fitted template's lid and lip margins moved onto the target's rims
// (BuildRigParams::align_margins_to_openings), in result.registration.positions.
MarginStage AlignMargins(const PreparedTemplate& prepared, const RawRig& target, const BuildRigParams& params,
                         BuildRigResult& result) {
  const auto start = std::chrono::steady_clock::now();
  MarginStage stage;
  if (params.align_margins_to_openings) {
    const Rig& template_rig = *prepared.rig;
    stage.margins = prepared.margins;
    // Rims of the skin only: the edges of ICT's eye layers are not lid margins.
    const std::vector<Triangle> skin =
        LargePartTriangles(target.positions, target.triangles, params.registration_min_part_area);
    stage.aligned = AlignMarginsToOpenings(result.registration.positions, template_rig.triangles(), stage.margins,
                                           target.positions, skin, params.openings);
    result.margin_vertices_aligned = stage.aligned.aligned_vertices;
    result.margin_mean_correction = stage.aligned.mean_correction;
  }
  result.timings.margin_seconds = SecondsSince(start);
  return stage;
}

// The fit taken back into the template's frame and units, where the
// transfer's anchors and thresholds mean what they say; a fit that had to
// crush the template is a mismatch.
std::vector<glm::vec3> FitInTemplateFrame(const Rig& template_rig, std::uint32_t region_vertex_count,
                                          const BuildRigParams& params, BuildRigResult& result) {
  const SimilarityTransform to_template = result.registration.rigid.Inverse();
  std::vector<glm::vec3> fitted(result.registration.positions.size());
  for (std::size_t v = 0; v < fitted.size(); ++v) fitted[v] = to_template.Apply(result.registration.positions[v]);
  result.deformation_percent = MeanDeformationPercent(template_rig.positions(), fitted, region_vertex_count);
  if (!(result.deformation_percent <= params.max_deformation_percent)) {
    throw RegistrationMismatchError(
        "the template does not match the target: fitting it moved the template's surface by " +
        std::to_string(result.deformation_percent) + " % of its size on average (limit " +
        std::to_string(params.max_deformation_percent) + " %; registration residual mean " +
        std::to_string(result.registration.residual.mean_percent) +
        " % of the target's diagonal); is the target a face, and are the landmarks right?");
  }
  return fitted;
}

// The template topology with the transferred shapes, in the template's frame
// (result.template_frame_rig: averages, caricatures and identity morphs
// compare several fits there) and returned in the target's frame: deltas
// rotate and scale with the similarity.
RawRig FittedRigInTargetFrame(const Rig& template_rig, std::span<const glm::vec3> fitted_in_template,
                              std::vector<RawBlendShape> shapes, RawRig& target, BuildRigResult& result) {
  result.template_frame_rig = RigBuilder::ToRaw(template_rig);
  result.template_frame_rig.positions.assign(fitted_in_template.begin(), fitted_in_template.end());
  result.template_frame_rig.normals.clear();
  result.template_frame_rig.shapes = shapes;
  const SimilarityTransform& to_target = result.registration.rigid;
  const auto scale = static_cast<float>(to_target.scale);
  for (RawBlendShape& shape : shapes) {
    for (glm::vec3& d : shape.position_deltas) d = scale * to_target.ApplyToDirection(d);
    for (glm::vec3& d : shape.normal_deltas) d = to_target.ApplyToDirection(d);
  }
  if (target.units == Units::kUnknown) target.units = InferTargetUnits(template_rig.units(), to_target.scale);
  RawRig fitted = RigBuilder::ToRaw(template_rig);
  fitted.positions = result.registration.positions;
  fitted.normals.clear();
  fitted.shapes = std::move(shapes);
  fitted.units = target.units;
  fitted.up_axis = target.up_axis;
  return fitted;
}

// The fitted rig's shapes onto the target's own vertices (result.rig), the
// target's rims snapped to the aligned margins.
void MapOntoTarget(const Rig& template_rig, RawRig fitted, const MarginStage& margins, RawRig target,
                   std::uint32_t region_vertex_count, const BuildRigParams& params, BuildRigResult& result) {
  std::string problem;
  std::optional<Rig> fitted_rig = RigBuilder::Build(fitted, &problem);
  if (!fitted_rig) throw InvalidInputError("the transferred template rig is invalid: " + problem);
  const std::vector<MarginDirection> rims =
      MarginDirections(margins.margins, margins.aligned.aligned, result.registration.positions);
  TopologyMappingParams mapping_params = params.mapping;
  mapping_params.openings = params.openings;
  const Mesh fitted_template{.positions = result.registration.positions,
                             .triangles = {template_rig.triangles().begin(), template_rig.triangles().end()}};
  const MouthSides mouth_sides = FindMouthSides(template_rig, result.registration.positions,
                                                result.registration.rigid.Inverse(), target.positions,
                                                target.triangles, region_vertex_count);
  result.mapping = ComputeTopologyMapping(fitted_template, NeutralMesh(target), mapping_params, rims, mouth_sides);
  result.rig = MapRigToTarget(*fitted_rig, result.mapping, std::move(target));
  result.fitted_rig = std::move(fitted);
}

}  // namespace

const char* ToString(BuildMode mode) {
  switch (mode) {
    case BuildMode::kClassic:
      return "classic";
    case BuildMode::kIdentityGradient:
      return "identity";
    case BuildMode::kDisplacement:
      return "displacement";
  }
  return "?";
}

std::optional<BuildMode> ParseBuildMode(std::string_view text) {
  for (BuildMode mode : {BuildMode::kClassic, BuildMode::kIdentityGradient, BuildMode::kDisplacement}) {
    if (text == ToString(mode)) return mode;
  }
  return std::nullopt;
}

RegistrationLandmarks PairLandmarks(const std::vector<std::uint32_t>& template_vertex_of,
                                    const FaceLandmarks& target_landmarks) {
  RegistrationLandmarks pairs;
  for (std::size_t i = 0; i < target_landmarks.points.size(); ++i) {
    const std::uint32_t index = i < target_landmarks.indices.size() ? target_landmarks.indices[i]
                                                                     : static_cast<std::uint32_t>(i);
    if (index >= template_vertex_of.size()) {
      throw InvalidInputError("landmark index " + std::to_string(index) + " is not a dlib landmark (0-" +
                              std::to_string(template_vertex_of.size() - 1) + ")");
    }
    pairs.template_vertices.push_back(template_vertex_of[index]);
    pairs.target_points.push_back(target_landmarks.points[i]);
    pairs.confidence.push_back(i < target_landmarks.confidence.size() ? target_landmarks.confidence[i] : 1.0f);
  }
  return pairs;
}

BuildRigResult BuildRig(const TemplatePreparation& prepared, RawRig target, const RegistrationLandmarks& landmarks,
                        const BuildRigParams& params) {
  const auto start = std::chrono::steady_clock::now();
  NonrigidIcpParams registration = params.registration;
  if (registration.region_vertex_count == 0) registration.region_vertex_count = prepared.region_vertex_count();
  registration.progress = [&](std::size_t done, std::size_t total) {
    if (params.progress) params.progress("register", done, total);
  };
  if (target.triangles.empty()) throw InvalidInputError("the target mesh has no triangles");
  std::size_t parts_left_out = 0;
  const std::vector<Triangle> skin = LargePartTriangles(target.positions, target.triangles,
                                                        params.registration_min_part_area, &parts_left_out);
  NonrigidIcpResult fit = NonrigidIcp(NeutralMesh(prepared.template_rig()),
                                      Mesh{.positions = target.positions, .triangles = skin}, landmarks, registration);
  BuildRigResult result = BuildRigOnRegistration(prepared, std::move(target), std::move(fit), params);
  result.stages.insert(result.stages.begin(), BuildStage{"register", result.timings.registration_seconds});
  result.target_parts_left_out = parts_left_out;
  result.timings.total_seconds = SecondsSince(start);
  return result;
}

BuildRigResult BuildRig(const TemplatePreparation& prepared, BuildTarget target, const RegistrationLandmarks& landmarks,
                        const BuildRigParams& params) {
  BuildRigResult result = BuildRig(prepared, std::move(target.rig), landmarks, params);
  result.target_mesh = std::move(target.mesh);
  return result;
}

BuildRigResult BuildRig(const Rig& template_rig, const FaceTemplateInfo& template_info, RawRig target,
                        const RegistrationLandmarks& landmarks, const BuildRigParams& params) {
  return BuildRig(TemplatePreparation(template_rig, template_info, params), std::move(target), landmarks, params);
}

BuildRigResult BuildRig(const Rig& template_rig, const FaceTemplateInfo& template_info, BuildTarget target,
                        const RegistrationLandmarks& landmarks, const BuildRigParams& params) {
  return BuildRig(TemplatePreparation(template_rig, template_info, params), std::move(target), landmarks, params);
}

BuildRigResult BuildRigOnRegistration(const Rig& template_rig, const FaceTemplateInfo& template_info, RawRig target,
                                      NonrigidIcpResult registered, const BuildRigParams& params) {
  return BuildRigOnRegistration(TemplatePreparation(template_rig, template_info, params), std::move(target),
                                std::move(registered), params);
}

BuildRigResult BuildRigOnRegistration(const TemplatePreparation& preparation, RawRig target,
                                      NonrigidIcpResult registered, const BuildRigParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const FaceTemplateInfo& template_info = preparation.info();
  if (registered.positions.size() != preparation.template_rig().vertex_count()) {
    throw InvalidInputError("the registration has " + std::to_string(registered.positions.size()) +
                            " vertices, the template " + std::to_string(preparation.template_rig().vertex_count()));
  }
  const std::uint32_t region_vertex_count = params.registration.region_vertex_count != 0
                                                ? params.registration.region_vertex_count
                                                : template_info.region.last + 1;
  BuildRigResult result;
  result.registration = std::move(registered);
  result.timings.registration_seconds = result.registration.timings.total_seconds;
  CheckResidual(result.registration.residual, params);

  StageRunner stage(params, result);
  // The template's variant for this target, made here when it was not
  // prepared before (one build): after the registration, whose memory is
  // gone by now, so that the build's peak does not hold it too.
  const PreparedTemplate* variant = nullptr;
  const MarginStage margins = stage.Run("align margins", [&] {
    variant = &preparation.For(target);
    return AlignMargins(*variant, target, params, result);
  });
  const PreparedTemplate& prepared = *variant;
  const Rig& template_rig = *prepared.rig;
  result.tongue_out_synthesised_from = prepared.tongue_out_synthesised_from;
  const std::vector<glm::vec3> fitted_in_template = stage.Run("to template frame", [&] {
    return FitInTemplateFrame(template_rig, region_vertex_count, params, result);
  });
  std::vector<RawBlendShape> shapes = stage.Run("transfer", [&] {
    return TransferExpressions(template_rig, fitted_in_template, region_vertex_count, params, result);
  });
  RawRig fitted = stage.Run("to target frame", [&] {
    return FittedRigInTargetFrame(template_rig, fitted_in_template, std::move(shapes), target, result);
  });
  result.timings.transfer_seconds = stage.SecondsOf("align margins") + stage.SecondsOf("to template frame") +
                                    stage.SecondsOf("transfer") + stage.SecondsOf("to target frame");
  stage.Run("map", [&] {
    MapOntoTarget(template_rig, std::move(fitted), margins, std::move(target), region_vertex_count, params, result);
    return 0;
  });
  result.timings.mapping_seconds = stage.SecondsOf("map");
  result.timings.total_seconds = result.timings.registration_seconds + SecondsSince(start);
  return result;
}

}  // namespace facerig
