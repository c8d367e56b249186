#include "face_animator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/shape_names.h"

namespace facerig::player {
namespace {

CharacterParams WithGaze(CharacterParams params, bool saccades) {
  params.gaze.enabled = params.gaze.enabled && saccades;
  return params;
}

}  // namespace

FaceAnimator::FaceAnimator(const Rig& rig, const IdleLifeParams& idle, const CharacterParams& params)
    : rig_(&rig),
      idle_(idle),
      character_rig_(CharacterRig::Build(rig)),
      character_(character_rig_, WithGaze(params, idle.saccades)),
      weights_(rig.shape_count(), 0.0f),
      positions_(rig.vertex_count()),
      normals_(rig.vertex_count()),
      blend_plan_(BlendPlan::Build(rig)),
      blend_state_(blend_plan_),
      up_(rig.up_axis() == UpAxis::kZ ? 2 : 1) {
  Blend();
  FindMouth();
}

void FaceAnimator::Blend() {
  const BlendJob job{rig_, weights_, normal_mode_, positions_, normals_, &blend_state_};
  job.Run();  // inputs are sized here and weights are finite: cannot fail
}

void FaceAnimator::FindMouth() {
  // The lips are what mouthFunnel / mouthPucker move most (jawOpen also moves
  // the chin). Their neutral centroid is the mouth; split at its height into
  // upper and lower lip vertices for the aperture.
  std::optional<std::size_t> shape;
  for (const char* name : {"mouthFunnel", "mouthPucker", "jawOpen"}) {
    if (const std::vector<std::size_t> found = FindShapesByArkitName(*rig_, name); !found.empty()) {
      shape = found.front();
      break;
    }
  }
  if (!shape) return;
  const BlendShapeView view = rig_->shape(*shape);
  std::vector<std::pair<float, std::uint32_t>> moved;
  for (std::size_t i = 0; i < view.vertex_indices.size(); ++i) {
    moved.emplace_back(glm::length(view.position_deltas[i]), view.vertex_indices[i]);
  }
  if (moved.empty()) return;
  std::sort(moved.begin(), moved.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const std::size_t keep = std::clamp<std::size_t>(moved.size() / 20, 1, 200);
  glm::vec3 sum(0.0f);
  for (std::size_t i = 0; i < keep; ++i) sum += rig_->positions()[moved[i].second];
  const glm::vec3 center = sum / static_cast<float>(keep);
  mouth_center_ = center;
  for (std::size_t i = 0; i < keep; ++i) {
    const std::uint32_t v = moved[i].second;
    (rig_->positions()[v][up_] >= center[up_] ? upper_lip_ : lower_lip_).push_back(v);
  }
  neutral_aperture_ = 0.0f;
  neutral_aperture_ = LipAperture();
}

float FaceAnimator::LipAperture() const {
  if (upper_lip_.empty() || lower_lip_.empty()) return 0.0f;
  const auto mean_up = [&](const std::vector<std::uint32_t>& lip) {
    float sum = 0.0f;
    for (std::uint32_t v : lip) sum += positions_[v][up_];
    return sum / static_cast<float>(lip.size());
  };
  return mean_up(upper_lip_) - mean_up(lower_lip_) - neutral_aperture_;
}

void FaceAnimator::Update(double time, FrameTimer* timer) {
  character_.Update(Seconds(time));
  const std::span<const float> character_weights = character_.weights();
  std::copy(character_weights.begin(), character_weights.end(), weights_.begin());
  if (idle_.head_motion) {
    // Incommensurate slow sines: never repeats visibly, zero at time 0.
    const auto t = static_cast<float>(time);
    const float deg = idle_.head_degrees;
    const float pitch = deg * 0.6f * (std::sin(0.31f * t) + 0.5f * std::sin(0.83f * t));
    const float yaw = deg * (std::sin(0.23f * t) + 0.4f * std::sin(0.61f * t + 0.0f));
    const float roll = deg * 0.35f * std::sin(0.17f * t);
    // Scene axes (Y up, Z towards the viewer): the renderer converts the rig's own axes.
    head_rotation_ = glm::rotate(glm::mat4(1.0f), glm::radians(yaw), glm::vec3(0, 1, 0)) *
                     glm::rotate(glm::mat4(1.0f), glm::radians(pitch), glm::vec3(1, 0, 0)) *
                     glm::rotate(glm::mat4(1.0f), glm::radians(roll), glm::vec3(0, 0, 1));
  }
  if (timer) timer->Mark(Stage::kUpdate);

  Blend();
  if (timer) timer->Mark(Stage::kBlend);
}

void FaceAnimator::SetNeutral() {
  std::fill(weights_.begin(), weights_.end(), 0.0f);
  Blend();
  head_rotation_ = glm::mat4(1.0f);
}

}  // namespace facerig::player
