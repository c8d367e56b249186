// The whole rig build (landmarks -> registration -> transfer -> the target's
// own topology) on re-meshed, rotated, rescaled random ICT faces, measured
// with issue 6's relative error and leak against the known answer.
#include "facerig/offline/rigging/rig_build.h"

#include <algorithm>
#include <limits>
#include <cstdio>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/mapping/mouth_sides.h"
#include "facerig/offline/mapping/topology_mapping.h"
#include "facerig/offline/geometry/self_intersection.h"
#include "facerig/runtime/io/obj.h"
#include "measure/mouth_interior.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

RawRig TargetRig(const test::RegistrationTarget& target) {
  RawRig raw;
  raw.positions = target.positions;
  raw.triangles = target.triangles;
  return raw;
}

// The shipped ICT descriptor (region, landmarks), read once.

RegistrationLandmarks TrueLandmarks(const test::RegistrationTarget& target) {
  FaceLandmarks landmarks;
  for (std::uint32_t i = 0; i < kDlibLandmarkCount; ++i) {
    landmarks.points.push_back(target.true_landmarks[i]);
    landmarks.indices.push_back(i);
    landmarks.confidence.push_back(i < 17 ? 0.2f : 1.0f);  // jaw points follow the silhouette
  }
  return PairLandmarks(test::IctTemplateInfo().landmark_vertices, landmarks);
}

// The largest length ratio of any edge of `triangles` between the neutral and
// the neutral plus `shape`.
float WorstStretch(const RawRig& rig, const RawBlendShape& shape) {
  std::vector<glm::vec3> moved = rig.positions;
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) moved[shape.vertex_indices[i]] += shape.position_deltas[i];
  float worst = 1.0f;
  for (const Triangle& t : rig.triangles) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
      const float rest = glm::distance(rig.positions[a], rig.positions[b]);
      if (rest > 0.0f) worst = std::max(worst, glm::distance(moved[a], moved[b]) / rest);
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("(shared data) build: a re-meshed, rotated, rescaled random ICT face gets all 53 expressions on its own "
          "vertices within issue 6's targets, in each mode",
          "[shared-data]") {
  const Rig& ict = test::IctRig();
  test::RegistrationTargetOptions options;
  options.seed = 3;
  const test::RegistrationTarget target = test::MakeRegistrationTarget(options);

  const BuildRigResult registered = BuildRig(ict, test::IctTemplateInfo(), TargetRig(target), TrueLandmarks(target));
  {
    // The inner parts (eyeballs, teeth, mouth socket, lashes) follow the fitted
    // skin: count skin x inner crossings of the fit against the true face's.
    auto skin_inner_crossings = [&](std::span<const glm::vec3> positions) {
      SelfIntersectionParams params;
      params.max_pairs = std::numeric_limits<std::size_t>::max();
      const SelfIntersectionResult found = FindSelfIntersections(facerig::test::MeshOf(positions, ict.triangles()), params);
      std::size_t count = 0;
      auto skin = [&](std::uint32_t t) {
        const Triangle& tri = ict.triangles()[t];
        const std::uint32_t head = test::IctTemplateInfo().region.last + 1;
        return tri[0] < head && tri[1] < head && tri[2] < head;
      };
      for (const auto& [a, b] : found.pairs) count += skin(a) != skin(b) ? 1 : 0;
      return count;
    };
    const std::size_t fitted = skin_inner_crossings(registered.registration.positions);
    const std::size_t truth = skin_inner_crossings(target.true_ict_positions);
    const std::size_t original = skin_inner_crossings(ict.positions());
    std::printf("skin x inner-part crossings: fitted %zu, true face %zu, template %zu\n", fitted, truth, original);
    // ICT itself has ~1,000 (lashes through lids, the mouth socket's rim): the
    // fit may add a few percent, not a tooth through the lip.
    CHECK(fitted <= original + original / 10 + 10);
  }
  {
    // A target vertex given a mouth side lies, on the true face, on a
    // template triangle of that side: the outer lips, whose bulge crosses the
    // seam's height, are left to the plain search.
    const MouthSides sides = FindMouthSides(ict, registered.registration.positions,
                                            registered.registration.rigid.Inverse(), target.positions,
                                            target.triangles, test::IctTemplateInfo().region.last + 1);
    REQUIRE(sides.target_vertex.size() == target.positions.size());
    const ClosestPointQuery truth(facerig::test::MeshOf(target.true_ict_positions, ict.triangles()));
    std::size_t sided = 0, wrong_side = 0;
    for (std::size_t v = 0; v < target.positions.size(); ++v) {
      if (sides.target_vertex[v] == MouthSide::kEither) continue;
      ++sided;
      const ClosestPointHit hit = truth.Find(target.positions[v]);
      if (hit.triangle >= 0 && sides.template_triangle[static_cast<std::size_t>(hit.triangle)] != sides.target_vertex[v]) {
        ++wrong_side;
      }
    }
    std::printf("mouth sides: %zu target vertices sided, %zu of them on the other side of the true face\n", sided,
                wrong_side);
    CHECK(sided > 100);
    // A few hundred: sides by the seam's height alone gave the lower lip's
    // bulge the upper side and made this face's expressions worse.
    CHECK(wrong_side < 300);
  }
  for (BuildMode mode : {BuildMode::kClassic, BuildMode::kIdentityGradient, BuildMode::kDisplacement}) {
    BuildRigParams params;
    params.mode = mode;
    // One registration, three transfers.
    const BuildRigResult built = BuildRigOnRegistration(ict, test::IctTemplateInfo(), TargetRig(target), registered.registration, params);
    std::string problem;
    const std::optional<Rig> rig = RigBuilder::Build(built.rig, &problem);
    REQUIRE(rig.has_value());
    // The target's own topology and coordinates, the template's shape names.
    REQUIRE(rig->vertex_count() == target.positions.size());
    CHECK(std::equal(rig->positions().begin(), rig->positions().end(), target.positions.begin()));
    CHECK(rig->shape_count() == ict.shape_count() + 1);  // and tongueOut, made from ICT's tongue
    CHECK(rig->FindShape("tongueOut").has_value());

    const test::BuiltRigErrors errors = test::MeasureBuiltRig(test::IctFaces(), ict, target, *rig);
    REQUIRE(errors.face_vertices > 1000);
    const double median = Percentile(errors.relative, 0.5), p90 = Percentile(errors.relative, 0.9);
    const double leak_median = Percentile(errors.leak, 0.5), leak_max = Percentile(errors.leak, 1.0);
    std::printf("build %s, seed %u (%zu target vertices, %.3g units/cm): relative error median %.3f p90 %.3f, leak "
                "median %.4f max %.4f; mapped %zu full, %zu partial, %zu none; register %.2f s, transfer %.2f s, "
                "map %.2f s\n",
                ToString(mode), options.seed, target.positions.size(), target.units_per_cm, median, p90, leak_median,
                leak_max, built.mapping.full_vertices, built.mapping.partial_vertices, built.mapping.unmapped_vertices,
                registered.timings.registration_seconds, built.timings.transfer_seconds, built.timings.mapping_seconds);
    for (std::size_t s = 0; s < errors.names.size(); ++s) {
      if (errors.relative[s] > 0.2) std::printf("  worst: %s %.3f\n", errors.names[s].c_str(), errors.relative[s]);
    }
    INFO(ToString(mode));
    CHECK(median <= 0.10);
    CHECK(p90 <= 0.20);
    CHECK(leak_median <= 0.02);
  }
}

}  // namespace facerig

namespace facerig {
namespace {

double MeanPairGap(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& upper,
                   const std::vector<std::uint32_t>& lower) {
  double sum = 0.0;
  for (std::size_t i = 0; i < upper.size(); ++i) sum += glm::length(positions[upper[i]] - positions[lower[i]]);
  return upper.empty() ? 0.0 : sum / static_cast<double>(upper.size());
}

// The pairs' gap across the opening: each closed pair's offset along its
// own direction at rest (upper minus lower), mean of the absolute values.
// A slide along the margin, as ICT's lids make, does not count.
double MeanPairGapAcross(std::span<const glm::vec3> rest, std::span<const glm::vec3> posed,
                         const std::vector<std::uint32_t>& upper, const std::vector<std::uint32_t>& lower) {
  double sum = 0.0;
  for (std::size_t i = 0; i < upper.size(); ++i) {
    const glm::vec3 across = glm::normalize(rest[upper[i]] - rest[lower[i]]);
    sum += std::abs(glm::dot(posed[upper[i]] - posed[lower[i]], across));
  }
  return upper.empty() ? 0.0 : sum / static_cast<double>(upper.size());
}

// How far the upper lid's vertices are from the lower lid's polyline, mean
// over the middle 80% of the upper lid: a closed eye measures 0 even where
// the lids slide sideways against each other (ICT's blink moves the lower
// lid inwards by 2 mm), which the pairs above count as a gap.
double MeanLidGap(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& upper,
                  const std::vector<std::uint32_t>& lower) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = upper.size() / 10; i < upper.size() - upper.size() / 10; ++i) {
    const glm::vec3 p = positions[upper[i]];
    float nearest = std::numeric_limits<float>::infinity();
    for (std::size_t k = 0; k + 1 < lower.size(); ++k) {
      const glm::vec3 a = positions[lower[k]];
      const glm::vec3 ab = positions[lower[k + 1]] - a;
      const float along = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
      nearest = std::min(nearest, glm::length(p - a - along * ab));
    }
    sum += nearest;
    ++count;
  }
  return count == 0 ? 0.0 : sum / static_cast<double>(count);
}

// How jagged the upper lid's motion is along it: mean distance of each
// vertex's delta from the mean of its two neighbours' (the lid's vertices in
// order along it).
double LidRoughness(std::span<const glm::vec3> neutral, std::span<const glm::vec3> moved,
                    const std::vector<std::uint32_t>& lid) {
  double sum = 0.0;
  for (std::size_t i = 1; i + 1 < lid.size(); ++i) {
    const glm::vec3 before = moved[lid[i - 1]] - neutral[lid[i - 1]];
    const glm::vec3 after = moved[lid[i + 1]] - neutral[lid[i + 1]];
    sum += glm::length(moved[lid[i]] - neutral[lid[i]] - 0.5f * (before + after));
  }
  return lid.size() < 3 ? 0.0 : sum / static_cast<double>(lid.size() - 2);
}

// +1 when the template's shape moves vertices on the +x side of the face.
float SideOfShape(const Rig& rig, std::string_view name) {
  const BlendShapeView shape = rig.shape(rig.FindShape(name).value());
  double weighted_x = 0.0;
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    weighted_x += glm::length(shape.position_deltas[i]) * rig.positions()[shape.vertex_indices[i]].x;
  }
  return weighted_x > 0.0 ? 1.0f : -1.0f;
}


}  // namespace

TEST_CASE("(shared data) build: onto ICT-topology faces, blinks stretch the lids no more than their own blinks, "
          "and the eyeballs stay still",
          "[shared-data]") {
  const Rig& ict = test::IctRig();
  const Mesh generic = ReadObj(test::IctDir() / "generic_neutral_mesh.obj");
  for (const char* identity : {"identity005", "identity011"}) {
    const Mesh face = ReadObj(test::IctDir() / (std::string(identity) + ".obj"));
    const RawRig target = ToRawRig(face);
    // No detection: a target on the template's topology has its landmark vertices.
    const std::optional<FaceLandmarks> landmarks =
        LandmarksOnTemplateTopology(ict, test::IctTemplateInfo(), target.positions, target.triangles);
    REQUIRE(landmarks.has_value());
    const BuildRigResult built =
        BuildRig(ict, test::IctTemplateInfo(), target, PairLandmarks(test::IctTemplateInfo().landmark_vertices, *landmarks));
    for (const char* name : {"eyeBlink_L", "eyeBlink_R"}) {
      const auto shape = std::find_if(built.rig.shapes.begin(), built.rig.shapes.end(),
                                      [&](const RawBlendShape& s) { return s.name == name; });
      REQUIRE(shape != built.rig.shapes.end());
      // The face's own blink: ICT's linear model, identity + (expression - generic neutral).
      const Mesh expression = ReadObj(test::IctDir() / (std::string(name) + ".obj"));
      RawBlendShape truth;
      truth.name = name;
      for (std::uint32_t v = 0; v < target.positions.size(); ++v) {
        truth.vertex_indices.push_back(v);
        truth.position_deltas.push_back(expression.positions[v] - generic.positions[v]);
      }
      // ICT's eyeballs are vertices 21451-24590: each target part is mapped
      // onto the template parts most of its vertices are near, so the front of
      // an eyeball does not take the lid's motion.
      float eyeball_move = 0.0f;
      for (std::size_t i = 0; i < shape->vertex_indices.size(); ++i) {
        if (shape->vertex_indices[i] >= 21451 && shape->vertex_indices[i] <= 24590) {
          eyeball_move = std::max(eyeball_move, glm::length(shape->position_deltas[i]));
        }
      }
      const float stretch = WorstStretch(built.rig, *shape), true_stretch = WorstStretch(built.rig, truth);
      std::printf("%s %s: worst edge stretch %.2fx (its own blink: %.2fx); eyeballs move %.2g cm\n", identity, name,
                  stretch, true_stretch, eyeball_move);
      INFO(identity << " " << name);
      CHECK(eyeball_move < 1e-3f);
      CHECK(stretch <= 1.3f * true_stretch);
    }
  }
}

TEST_CASE("(shared data) build: the ICT template onto the built-in default head, another topology, with detected "
          "landmarks: eyes blink, the jaw opens, the smile is on its side",
          "[shared-data]") {
  const Rig& ict = test::IctRig();
  DefaultHeadFeatures features;
  const Rig own_rig = BuildDefaultHead(&features);
  RawRig head = RigBuilder::ToRaw(own_rig);
  head.shapes.clear();  // only the template's shapes, none of the head's own

  // dlib misses this stylized head's eyes (2.8 cm wide against 2.1, the
  // upper lids on the brows); its eyes are holes in the skin, and the eye
  // points go onto their margins (LandmarkParams::fit_eyes_to_openings).
  // Without that, the template's eye opening registered above the head's and
  // its blink did not close the head's eyes.
  LandmarkDetector detector;
  const LandmarkResult detected = detector.Detect(facerig::test::MeshOf(head.positions, head.triangles));
  CHECK(detected.eyes_fitted == 2);
  const BuildRigResult built =
      BuildRig(ict, test::IctTemplateInfo(), head, PairLandmarks(test::IctTemplateInfo().landmark_vertices, detected.landmarks));
  // The fitted template's lid margins went onto the head's eye rims (both
  // eyes, upper and lower: ICT's blinks give 28 margin vertices per eye).
  std::printf("default head: %zu template margin vertices aligned onto the eye rims, mean move %.3f cm\n",
              built.margin_vertices_aligned, built.margin_mean_correction);
  CHECK(built.margin_vertices_aligned >= 40);
  const std::optional<Rig> rig = RigBuilder::Build(built.rig);
  REQUIRE(rig.has_value());
  REQUIRE(rig->vertex_count() == head.positions.size());
  CHECK(rig->shape_count() == ict.shape_count() + 1);  // and tongueOut (the head's own shapes were dropped)
  // A whole head onto a whole head: nearly every vertex has a template counterpart.
  CHECK(built.mapping.unmapped_vertices < head.positions.size() / 100);

  const std::span<const glm::vec3> neutral = rig->positions();
  for (const char* blink : {"eyeBlink_L", "eyeBlink_R"}) {
    const std::size_t eye = (SideOfShape(ict, blink) > 0.0f) == (features.eye_centres[0].x > 0.0f) ? 0 : 1;
    const std::vector<glm::vec3> closed = PoseWithShape(*rig, blink);
    const double open_gap = MeanPairGap(neutral, features.upper_lid[eye], features.lower_lid[eye]);
    const double closed_gap = MeanPairGap(closed, features.upper_lid[eye], features.lower_lid[eye]);
    const double closed_across = MeanPairGapAcross(neutral, closed, features.upper_lid[eye], features.lower_lid[eye]);
    const double other_open = MeanPairGap(neutral, features.upper_lid[1 - eye], features.lower_lid[1 - eye]);
    const double other_after = MeanPairGap(closed, features.upper_lid[1 - eye], features.lower_lid[1 - eye]);
    const double lid_gap = MeanLidGap(closed, features.upper_lid[eye], features.lower_lid[eye]);
    const double roughness = LidRoughness(neutral, closed, features.upper_lid[eye]);
    std::printf("default head %s: lid gap %.3f -> %.3f cm (%.3f across the opening), upper lid to lower lid %.3f cm "
                "(other eye %.3f -> %.3f), upper lid roughness %.4f cm\n",
                blink, open_gap, closed_gap, closed_across, lid_gap, other_open, other_after, roughness);
    // Measured: pairs 0.586 -> 0.119-0.127 cm (the lids slide past each
    // other as ICT's do), upper lid to lower lid 0.007-0.011 (1-2% of the
    // opening). Without closing the head's own rims
    // (OpeningParams::rim_closing_ratio): 0.031-0.040, a slit in the
    // middle; keeping the template's contact offsets: 0.056-0.066; before the
    // margins were aligned onto the rims: 0.137; before the transfer kept the
    // lids' contact: 0.26 (pairs).
    // The pairs' whole offset also holds the lids' slide along the margin,
    // which follows the landmarks dlib finds on the head: 0.13-0.19 cm with
    // the head's eyes unchanged and only its hair or chin different (issue
    // 34), one eye against the other up to 0.05 cm on this symmetric head.
    // Across the opening the lids meet.
    CHECK(closed_across < 0.25 * open_gap);
    CHECK(lid_gap < 0.04 * open_gap);
    // The closed upper lid's edge is smooth: 0.0043-0.0048 cm, against
    // 0.022-0.024 without OpeningParams::rim_smoothing_radius (a step
    // of up to 2.7 mm where the template's margin ended before the head's rim).
    CHECK(roughness < 0.01);
    CHECK(other_after > 0.9 * other_open);
  }
  const std::vector<glm::vec3> jaw_open = PoseWithShape(*rig, "jawOpen");
  const double lips_rest = MeanPairGap(neutral, features.upper_lip, features.lower_lip);
  const double lips_open = MeanPairGap(jaw_open, features.upper_lip, features.lower_lip);
  std::printf("default head jawOpen: lip gap %.3f -> %.3f cm\n", lips_rest, lips_open);
  CHECK(lips_open > lips_rest + 1.0);  // centimetres: ICT's jawOpen opens the lips by ~2 cm
  // No curtain across the opened mouth: the upper lip, its inner side and
  // the palate stay with the head (each side of the mouth searches only the
  // template's same side, a vertex inside the mouth the side of the lip its
  // surface leads to); without sides they took ICT's lower lip and tongue,
  // with sides by height alone the back of the mouth sack (where its roof
  // and floor meet) took ICT's tongue and pulled the palate's back wall down.
  const MouthCurtain curtain = MeasureMouthCurtain(own_rig, *rig, features);
  const LipFold fold = MeasureLipFold(*rig, features);
  std::printf("default head jawOpen: %zu upper-lip and %zu palate vertices of %zu in the upper mouth follow the jaw "
              "(worst %.2f of the lower lip's motion; mouth sides: %zu upper, %zu lower vertices); fold under the "
              "lower lip %.1f degrees (its own jawOpen: %.1f)\n",
              curtain.skin_on_jaw, curtain.sack_on_jaw, curtain.upper_vertices, curtain.worst_ratio,
              built.mapping.mouth_upper_vertices, built.mapping.mouth_lower_vertices, fold.degrees,
              MeasureLipFold(own_rig, features).degrees);
  CHECK(curtain.upper_vertices > 100);
  CHECK(curtain.skin_on_jaw == 0);
  CHECK(curtain.sack_on_jaw == 0);
  CHECK(curtain.worst_ratio < 0.5f);
  // The same mapping without the mouth's sides hangs the curtain.
  const std::optional<Rig> fitted_rig = RigBuilder::Build(built.fitted_rig);
  REQUIRE(fitted_rig.has_value());
  TopologyMappingParams mapping_params = BuildRigParams{}.mapping;
  mapping_params.openings = BuildRigParams{}.openings;
  const Mesh fitted_template{.positions = built.registration.positions,
                             .triangles = {ict.triangles().begin(), ict.triangles().end()}};
  const TopologyMapping unsided = ComputeTopologyMapping(fitted_template, NeutralMesh(head), mapping_params);
  const std::optional<Rig> curtained = RigBuilder::Build(MapRigToTarget(*fitted_rig, unsided, head));
  REQUIRE(curtained.has_value());
  const MouthCurtain unsided_curtain = MeasureMouthCurtain(own_rig, *curtained, features);
  std::printf("default head jawOpen without mouth sides: %zu upper-lip and %zu palate vertices follow the jaw\n",
              unsided_curtain.skin_on_jaw, unsided_curtain.sack_on_jaw);
  CHECK(unsided_curtain.skin_on_jaw + unsided_curtain.sack_on_jaw > 20);

  for (const char* smile : {"mouthSmile_L", "mouthSmile_R"}) {
    const std::size_t corner =
        (SideOfShape(ict, smile) > 0.0f) == (neutral[features.mouth_corners[0]].x > 0.0f) ? 0 : 1;
    const std::vector<glm::vec3> smiling = PoseWithShape(*rig, smile);
    const glm::vec3 moved = smiling[features.mouth_corners[corner]] - neutral[features.mouth_corners[corner]];
    const glm::vec3 other =
        smiling[features.mouth_corners[1 - corner]] - neutral[features.mouth_corners[1 - corner]];
    std::printf("default head %s: corner moves (%.3f, %.3f, %.3f), the other %.3f cm\n", smile, moved.x, moved.y,
                moved.z, glm::length(other));
    CHECK(moved.y > 0.3f);                                                // up
    CHECK(moved.x * neutral[features.mouth_corners[corner]].x > 0.0f);     // outward
    CHECK(glm::length(other) < 0.3f * glm::length(moved));
  }
}

}  // namespace facerig

namespace facerig {

TEST_CASE("build: the template descriptor's region must lie within the template", "[rig_build]") {
  const Rig grid = test::MakeGridRig(6, 1);
  FaceTemplateInfo info = DeriveFaceTemplateInfo(grid);
  info.region.last = static_cast<std::uint32_t>(grid.vertex_count());
  RawRig target = RigBuilder::ToRaw(grid);
  REQUIRE_THROWS_WITH(BuildRig(grid, info, target, RegistrationLandmarks{}),
                      Catch::Contains("region ends at vertex " + std::to_string(grid.vertex_count())));
}

}  // namespace facerig
