// OpenGL 3.3 core rendering of a rig: skin-like shading, eyes with iris and
// pupil, a material per rig part chosen by its name, and an orbit camera
// framed from the neutral's bounding box. Needs a current GL context (SDL
// window or HeadlessGlContext) for its whole life.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"
#include "media_writer.h"

namespace facerig::player {

enum class Material : std::uint8_t {
  kSkin, kSclera, kIris, kPupil, kTeeth, kGums, kTongue, kMouthInner, kHidden,
};
// The material for a rig part name: the default head's names ("skin",
// "eye_white_L", "iris_R", ...) and ICT-FaceKit's ("M_Face", "M_ScleraLeft",
// ...). ICT's transparent overlays (eye occlusion, lacrimal fluid, eye blend)
// are kHidden: drawn opaque they would cover the eyes with grey shells. So are
// eyelashes: they are alpha-textured cards, which without their texture draw
// as a thick black band around the eye.
Material MaterialForPart(std::string_view part_name);
const char* ToString(Material material);

// Orbit camera around a target, in scene space (metres, Y up).
struct OrbitCamera {
  glm::vec3 target{0.0f};
  float distance = 1.0f;
  float yaw_degrees = 0.0f;    // 0: looking at the face from the front (+Z)
  float pitch_degrees = 0.0f;  // positive: from above
  float fov_degrees = 30.0f;

  void Orbit(float dx_degrees, float dy_degrees);
  void Zoom(float steps);  // positive: closer
  glm::mat4 View() const;
  glm::mat4 Projection(float aspect) const;
};

class FaceRenderer {
 public:
  // Uploads the rig's topology and compiles the shaders. Throws
  // std::runtime_error with the GL info log when a shader fails.
  explicit FaceRenderer(const Rig& rig);
  ~FaceRenderer();
  FaceRenderer(const FaceRenderer&) = delete;
  FaceRenderer& operator=(const FaceRenderer&) = delete;

  // Replaces the dynamic vertex data (glBufferSubData). Sizes must be vertex_count().
  void Upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals);
  // Draws into the bound framebuffer, viewport (0,0,width,height), clearing it first.
  void Draw(int width, int height, const glm::mat4& head_rotation);

  OrbitCamera& camera() { return camera_; }
  // Frames the neutral's bounding box from the front.
  void ResetCamera();
  // Pixel position (x right, y down from the top-left) of a point in rig units.
  glm::vec2 Project(const glm::vec3& rig_point, int width, int height,
                    const glm::mat4& head_rotation) const;
  // Rig units -> scene (metres, Y up).
  const glm::mat4& rig_to_scene() const { return rig_to_scene_; }
  // Size of the framed head in scene units (bounding-box diagonal, metres).
  float scene_size() const { return scene_size_; }

 private:
  struct DrawRange {
    std::uint32_t first_index = 0;
    std::uint32_t index_count = 0;
    Material material = Material::kSkin;
    std::string name;
  };
  // Construction steps, in this order.
  void SetDrawRanges(const Rig& rig);      // a range per part with its material; procedural_pupil_
  void FrameVisibleParts(const Rig& rig);  // scene box and neck pivot from the visible parts
  void CompileShaders();                   // program_ and the uniform locations
  void CreateBuffers(const Rig& rig, std::span<const float> radial);
  glm::mat4 ModelMatrix(const glm::mat4& head_rotation) const;

  std::size_t vertex_count_ = 0;
  std::vector<DrawRange> ranges_;
  bool procedural_pupil_ = false;  // iris parts draw their own pupil (rig has no pupil part)
  glm::mat4 rig_to_scene_{1.0f};
  glm::vec3 scene_center_{0.0f}, scene_lo_{0.0f}, scene_hi_{0.0f};
  glm::vec3 neck_pivot_{0.0f};
  float scene_size_ = 1.0f;
  OrbitCamera camera_;

  unsigned program_ = 0, vao_ = 0, position_vbo_ = 0, normal_vbo_ = 0, radial_vbo_ = 0, ebo_ = 0;
  int u_model_ = -1, u_view_ = -1, u_projection_ = -1, u_normal_matrix_ = -1;
  int u_material_ = -1, u_base_color_ = -1, u_procedural_pupil_ = -1, u_camera_position_ = -1;
};

// Renders into an offscreen framebuffer (multisampled, resolved for reading back).
class OffscreenTarget {
 public:
  // `samples`: MSAA samples, 0 for none.
  OffscreenTarget(int width, int height, int samples = 4);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  void Bind();
  // Resolves the samples and reads the image (rows top to bottom).
  void Read(Image* image);

 private:
  int width_, height_;
  unsigned msaa_fbo_ = 0, msaa_color_ = 0, msaa_depth_ = 0;
  unsigned resolve_fbo_ = 0, resolve_color_ = 0;
};

// Compiles and links a vertex + fragment program. Throws std::runtime_error with the log.
unsigned CompileProgram(const char* vertex_source, const char* fragment_source, const char* name);

}  // namespace facerig::player
