// OpenGL 3.3 core rendering of a rig: the rig's own materials and textures
// (base colour, normal map, alpha mask or blend, double-sided), skin-like
// shading, eyes with iris and pupil, a colour chosen by the part's name for
// parts without a material, and an orbit camera framed from the neutral's
// bounding box. Needs a current GL context (SDL
// window or HeadlessGlContext) for its whole life.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"
#include "media_writer.h"

namespace facerig::player {
class RigTextures;
struct PartLook;
}  // namespace facerig::player

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
  // Uploads the rig's topology, UVs and images and compiles the shaders.
  // Throws std::runtime_error with the GL info log when a shader fails. An
  // image that does not decode is not an error: see problems().
  explicit FaceRenderer(const Rig& rig);
  ~FaceRenderer();
  FaceRenderer(const FaceRenderer&) = delete;
  FaceRenderer& operator=(const FaceRenderer&) = delete;

  // Replaces the dynamic vertex data (glBufferSubData). Sizes must be vertex_count().
  void Upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals);
  // Draws into the bound framebuffer, viewport (0,0,width,height), clearing it
  // first: opaque and masked parts, then blended ones back to front.
  void Draw(int width, int height, const glm::mat4& head_rotation);
  // Base colour only, no lighting (to check textures and colours).
  void set_unlit(bool unlit) { unlit_ = unlit; }
  // What went wrong preparing the rig's look (an image that does not decode,
  // textures without UVs), one sentence each; the parts concerned draw with
  // their colour.
  const std::vector<std::string>& problems() const { return problems_; }

  OrbitCamera& camera() { return camera_; }
  // Frames the neutral's bounding box from the front; with a jawOpen, the
  // frame reaches below the chin.
  void ResetCamera();
  // Pixel position (x right, y down from the top-left) of a point in rig units.
  glm::vec2 Project(const glm::vec3& rig_point, int width, int height,
                    const glm::mat4& head_rotation) const;
  // Rig units -> scene (metres, Y up).
  const glm::mat4& rig_to_scene() const { return rig_to_scene_; }
  // Size of the framed head in scene units (bounding-box diagonal, metres).
  float scene_size() const { return scene_size_; }

 private:
  struct Uniforms {
    int model = -1, view = -1, projection = -1, normal_matrix = -1, camera_position = -1;
    int material = -1, base_color = -1, procedural_pupil = -1, unlit = -1;
    int wrap = -1, shininess = -1, specular = -1, rim = -1, ambient = -1;
    int base_texture = -1, normal_texture = -1;
    int alpha_mode = -1, alpha_cutoff = -1;
  };
  // One compiled fragment-shader variant (face_shaders.h's features).
  struct ShaderVariant {
    unsigned program = 0;  // 0: not compiled (no part needs it)
    Uniforms u;
  };
  struct DrawRange;
  // Construction steps, in this order.
  void SetDrawRanges(const Rig& rig);      // a range per visible part with its look; procedural_pupil_
  void FrameVisibleParts(const Rig& rig);  // scene box and neck pivot from the visible parts
  void CompileShaders();                   // the variants the parts need, and their uniform locations
  void CreateBuffers(const Rig& rig, std::span<const float> radial, std::span<const float> mouth_light);
  void CreateUvBuffer(const Rig& rig);
  glm::mat4 ModelMatrix(const glm::mat4& head_rotation) const;
  // Per frame.
  void SetFrameUniforms(const ShaderVariant& variant, int width, int height, const glm::mat4& model);
  void SortBlendedBackToFront(const glm::mat4& model_view);
  void DrawRangeOf(const DrawRange& range, unsigned* current_variant);

  std::size_t vertex_count_ = 0;
  std::vector<DrawRange> ranges_;          // opaque and masked parts first, then blended ones
  std::size_t first_blended_ = 0;          // ranges_[first_blended_..] blend
  std::vector<std::pair<float, std::size_t>> blend_order_;  // (view depth, range), reused every frame
  std::unique_ptr<RigTextures> textures_;
  std::vector<std::string> problems_;
  bool unlit_ = false;
  bool procedural_pupil_ = false;  // iris parts draw their own pupil (rig has no pupil part)
  glm::mat4 rig_to_scene_{1.0f};
  glm::vec3 scene_center_{0.0f}, scene_lo_{0.0f}, scene_hi_{0.0f};
  glm::vec3 neck_pivot_{0.0f};
  std::optional<glm::vec3> chin_;  // scene space: the bottom of the chin, when the rig has a jawOpen
  float scene_size_ = 1.0f;
  OrbitCamera camera_;

  std::vector<ShaderVariant> variants_;  // indexed by features
  unsigned vao_ = 0, position_vbo_ = 0, normal_vbo_ = 0, radial_vbo_ = 0, mouth_light_vbo_ = 0, uv_vbo_ = 0, ebo_ = 0;
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
