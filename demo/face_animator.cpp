#include "face_animator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::player {
namespace {

// splitmix64: a tiny, seedable, deterministic generator (headless frames must repeat).
double NextUniform(std::uint64_t* state) {
  std::uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

float SmoothStep(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

}  // namespace

FaceAnimator::FaceAnimator(const Rig& rig, const IdleLifeParams& idle, const CharacterParams& params)
    : rig_(&rig),
      idle_(idle),
      character_rig_(CharacterRig::Build(rig)),
      character_(character_rig_, params),
      weights_(rig.shape_count(), 0.0f),
      positions_(rig.positions().begin(), rig.positions().end()),
      normals_(rig.vertex_count()),
      rng_(idle.seed),
      up_(rig.up_axis() == UpAxis::kZ ? 2 : 1) {
  static const char* const kEyeNames[kEyeShapeCount] = {
      "eyeLookIn_L", "eyeLookOut_L", "eyeLookUp_L", "eyeLookDown_L",
      "eyeLookIn_R", "eyeLookOut_R", "eyeLookUp_R", "eyeLookDown_R"};
  has_eye_shapes_ = true;
  for (int i = 0; i < kEyeShapeCount; ++i) {
    const std::optional<std::size_t> shape = rig.FindShape(kEyeNames[i]);
    eye_shapes_[i] = shape ? static_cast<int>(*shape) : -1;
    has_eye_shapes_ = has_eye_shapes_ && shape.has_value();
  }
  next_saccade_ = idle_.saccade_min_interval +
                  NextUniform(&rng_) * (idle_.saccade_max_interval - idle_.saccade_min_interval);
  ComputeVertexNormals(positions_, rig.triangles(), normals_);
  FindMouth();
}

void FaceAnimator::FindMouth() {
  // The lips are what mouthFunnel / mouthPucker move most (jawOpen also moves
  // the chin). Their neutral centroid is the mouth; split at its height into
  // upper and lower lip vertices for the aperture.
  std::optional<std::size_t> shape;
  for (const char* name : {"mouthFunnel", "mouthPucker", "jawOpen"}) {
    if ((shape = rig_->FindShape(name))) break;
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

void FaceAnimator::UpdateSaccades(double time) {
  if (time < last_time_) {  // a seek backwards restarts the idle life, deterministically
    rng_ = idle_.seed;
    next_saccade_ = idle_.saccade_min_interval +
                    NextUniform(&rng_) * (idle_.saccade_max_interval - idle_.saccade_min_interval);
    saccade_start_ = 0.0;
    gaze_from_[0] = gaze_from_[1] = gaze_to_[0] = gaze_to_[1] = 0.0f;
  }
  last_time_ = time;
  while (time >= next_saccade_) {
    gaze_from_[0] = gaze_to_[0];
    gaze_from_[1] = gaze_to_[1];
    // Mostly small glances around the centre; now and then back to the middle.
    const bool recentre = NextUniform(&rng_) < 0.3;
    gaze_to_[0] = recentre ? 0.0f : static_cast<float>(NextUniform(&rng_) * 2.0 - 1.0);
    gaze_to_[1] = recentre ? 0.0f : static_cast<float>(NextUniform(&rng_) * 1.2 - 0.6);
    saccade_start_ = next_saccade_;
    next_saccade_ += idle_.saccade_min_interval +
                     NextUniform(&rng_) * (idle_.saccade_max_interval - idle_.saccade_min_interval);
  }
  // A saccade takes ~40 ms.
  const float t = SmoothStep(static_cast<float>((time - saccade_start_) / 0.04));
  for (int i = 0; i < 2; ++i) gaze_[i] = gaze_from_[i] + (gaze_to_[i] - gaze_from_[i]) * t;

  const float a = idle_.saccade_amplitude;
  const float right = std::max(gaze_[0], 0.0f) * a, left = std::max(-gaze_[0], 0.0f) * a;
  const float up = std::max(gaze_[1], 0.0f) * a, down = std::max(-gaze_[1], 0.0f) * a;
  // Looking to the character's left: the left eye looks out, the right eye in.
  const float targets[kEyeShapeCount] = {right, left, up, down, left, right, up, down};
  for (int i = 0; i < kEyeShapeCount; ++i) {
    float& w = weights_[static_cast<std::size_t>(eye_shapes_[i])];
    // Added to what Character set (e.g. eyeLookDown from a blink or emotion).
    w = std::min(1.0f, w + targets[i]);
  }
}

void FaceAnimator::Update(double time, FrameTimer* timer) {
  character_.Update(time);
  const std::span<const float> character_weights = character_.weights();
  std::copy(character_weights.begin(), character_weights.end(), weights_.begin());
  if (idle_.saccades && has_eye_shapes_) UpdateSaccades(time);
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

  BlendJob job;
  job.rig = rig_;
  job.weights = weights_;
  job.normal_mode = NormalMode::kNone;
  job.out_positions = positions_;
  job.Run();  // inputs are sized here and weights are finite: cannot fail
  if (timer) timer->Mark(Stage::kBlend);
  ComputeVertexNormals(positions_, rig_->triangles(), normals_);
  if (timer) timer->Mark(Stage::kNormals);
}

void FaceAnimator::SetNeutral() {
  std::fill(weights_.begin(), weights_.end(), 0.0f);
  std::copy(rig_->positions().begin(), rig_->positions().end(), positions_.begin());
  ComputeVertexNormals(positions_, rig_->triangles(), normals_);
  head_rotation_ = glm::mat4(1.0f);
}

}  // namespace facerig::player
