#include "facerig/offline/rigging/lid_choice.h"

#include <algorithm>
#include <exception>
#include <future>

#include <glm/geometric.hpp>

#include "facerig/runtime/shape_names.h"
#include "rigging/blas_threads.h"

namespace facerig {
namespace {

bool IsBlink(std::string_view shape_name) { return CanonicalShapeNameOf(shape_name).base == "eyeblink"; }

bool HasBlinks(const Rig& rig) {
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    if (IsBlink(rig.shape_name(s))) return true;
  }
  return false;
}

float WorstEdgeStretch(const RawRig& rig, const std::vector<glm::vec3>& moved) {
  float stretch = 1.0f;
  for (const Triangle& t : rig.triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      const float rest = glm::distance(rig.positions[a], rig.positions[b]);
      if (rest > 0.0f) stretch = std::max(stretch, glm::distance(moved[a], moved[b]) / rest);
    }
  }
  return stretch;
}

// One build, or the error that stopped it.
struct Attempt {
  std::optional<BuildRigResult> built;
  std::exception_ptr error;
  float stretch = 0.0f;
};

Attempt TryBuild(const TemplatePreparation& prepared, BuildTarget target, const RegistrationLandmarks& pairs,
                 const BuildRigParams& params) {
  Attempt attempt;
  try {
    attempt.built = BuildRig(prepared, std::move(target), pairs, params);
    attempt.stretch = WorstBlinkStretch(attempt.built->rig).value_or(1.0f);
  } catch (...) {
    attempt.error = std::current_exception();
  }
  return attempt;
}

}  // namespace

std::optional<float> WorstBlinkStretch(const RawRig& rig) {
  std::optional<float> worst;
  std::vector<glm::vec3> moved;
  for (const RawBlendShape& shape : rig.shapes) {
    if (!IsBlink(shape.name)) continue;
    moved = rig.positions;
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      moved[shape.vertex_indices[i]] += shape.position_deltas[i];
    }
    worst = std::max(worst.value_or(1.0f), WorstEdgeStretch(rig, moved));
  }
  return worst;
}

FaceLandmarks TrustingDoubtfulLids(const FaceLandmarks& landmarks, const DoubtfulLidPoints& doubtful) {
  FaceLandmarks trusting = landmarks;
  for (std::size_t i = 0; i < trusting.confidence.size(); ++i) {
    const std::uint32_t k = i < trusting.indices.size() ? trusting.indices[i] : static_cast<std::uint32_t>(i);
    if (k < doubtful.points.size() && doubtful.points[k] && k < doubtful.confidence.size()) {
      trusting.confidence[i] = doubtful.confidence[k];
    }
  }
  return trusting;
}

BuildRigResult BuildRigChoosingLids(const TemplatePreparation& prepared, const BuildTarget& target,
                                    const std::vector<std::uint32_t>& template_vertex_of,
                                    const FaceLandmarks& landmarks, const DoubtfulLidPoints& doubtful,
                                    const BuildRigParams& params, LidChoice* choice) {
  const RegistrationLandmarks dropping = PairLandmarks(template_vertex_of, landmarks);
  if (doubtful.points.none() || !HasBlinks(prepared.template_rig())) {
    if (choice) *choice = LidChoice{};
    return BuildRig(prepared, target, dropping, params);
  }
  // Both at once, with one BLAS thread each: a build's factorizations keep
  // about one core busy, so the two take ~1.2x one build's time, not 2x.
  const ScopedBlasThreads one_blas_thread(1);
  BuildRigParams quiet = params;
  quiet.progress = nullptr;  // one progress report: the dropping build's
  const RegistrationLandmarks trusting = PairLandmarks(template_vertex_of, TrustingDoubtfulLids(landmarks, doubtful));
  std::future<Attempt> trusted_build =
      std::async(std::launch::async, [&] { return TryBuild(prepared, target, trusting, quiet); });
  Attempt dropped = TryBuild(prepared, target, dropping, params);
  Attempt trusted = trusted_build.get();
  if (dropped.error && trusted.error) std::rethrow_exception(dropped.error);

  LidChoice made{.tried = true, .trusted_stretch = trusted.stretch, .dropped_stretch = dropped.stretch};
  made.trusted = !trusted.error && (dropped.error || trusted.stretch < dropped.stretch);
  if (choice) *choice = made;
  return std::move(made.trusted ? *trusted.built : *dropped.built);
}

}  // namespace facerig
