// One character's per-frame animation: Character::Update (speech, emotions,
// blinks, gaze), head motion, then BlendJob positions and normals written only
// where they moved (a BlendState; normals blended from each shape's change of
// the recomputed ones, kBlendRecomputedDeltas, as a crowd would). Also finds
// the rig's mouth, for the camera, the tests and the HUD. Buffers are sized
// once in the constructor; Update allocates nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/rig.h"
#include "frame_timing.h"

namespace facerig::player {

struct IdleLifeParams {
  bool head_motion = true;  // slow smooth head rotation (model matrix)
  bool saccades = true;     // Character's gaze (CharacterParams::gaze.enabled)
  float head_degrees = 2.5f;
};

class FaceAnimator {
 public:
  // `rig` must outlive the animator.
  FaceAnimator(const Rig& rig, const IdleLifeParams& idle = {}, const CharacterParams& params = {});
  FaceAnimator(const FaceAnimator&) = delete;
  FaceAnimator& operator=(const FaceAnimator&) = delete;

  Character& character() { return character_; }
  const Character& character() const { return character_; }
  const CharacterRig& character_rig() const { return character_rig_; }
  const Rig& rig() const { return *rig_; }

  // Weights at `time` (seconds on the animation clock), then positions and
  // normals. With a timer, marks kUpdate and kBlend.
  void Update(double time, FrameTimer* timer = nullptr);
  // Neutral positions and normals (all weights 0, no head motion), for tests.
  void SetNeutral();
  // How Update makes the normals (kBlendRecomputedDeltas unless set; the
  // tests compare it with kRecompute). Takes effect at the next Update.
  void SetNormalMode(NormalMode mode) { normal_mode_ = mode; }

  std::span<const float> weights() const { return weights_; }
  std::span<const glm::vec3> positions() const { return positions_; }
  std::span<const glm::vec3> normals() const { return normals_; }
  // What the last blend wrote (it writes only what moved).
  BlendWork last_blend_work() const { return blend_state_.LastWork(); }
  // Head rotation in scene axes (Y up, +Z towards the viewer), about the neck;
  // identity with head_motion off and at time 0.
  const glm::mat4& head_rotation() const { return head_rotation_; }
  bool has_eye_shapes() const { return character_rig_.gaze_shapes().has_value(); }

  // Centre of the lips in the neutral mesh (rig units), from the vertices that
  // the lip shapes move most; nullopt when the rig has no lip shapes.
  std::optional<glm::vec3> mouth_center() const { return mouth_center_; }
  // Vertical distance between the upper and lower lip in the current
  // positions, minus the neutral's (rig units; 0 at rest, larger when open).
  float LipAperture() const;

 private:
  void FindMouth();
  void Blend();

  const Rig* rig_;
  IdleLifeParams idle_;
  CharacterRig character_rig_;
  Character character_;
  std::vector<float> weights_;
  std::vector<glm::vec3> positions_;
  std::vector<glm::vec3> normals_;
  BlendPlan blend_plan_;
  BlendState blend_state_;  // what positions_ and normals_ hold
  NormalMode normal_mode_ = NormalMode::kBlendRecomputedDeltas;
  glm::mat4 head_rotation_{1.0f};

  std::optional<glm::vec3> mouth_center_;
  std::vector<std::uint32_t> upper_lip_, lower_lip_;
  float neutral_aperture_ = 0.0f;
  int up_ = 1;  // index of the up coordinate (1: Y, 2: Z)
};

}  // namespace facerig::player
