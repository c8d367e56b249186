#include "face_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>
#include <span>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "face_materials.h"
#include "face_shaders.h"
#include "gl_textures.h"
#include "iris_radial.h"
#include "mouth_light.h"
#include "facerig/runtime/shape_names.h"

namespace facerig::player {
namespace {

// Rig units and axes -> scene metres with Y up (glTF's frame).
glm::mat4 RigToScene(const Rig& rig) {
  const auto metres = static_cast<float>(MetresPerUnit(rig.units()));
  glm::mat4 rig_to_scene = glm::scale(glm::mat4(1.0f), glm::vec3(metres));
  if (rig.up_axis() == UpAxis::kZ) {
    // Z up, -Y towards the viewer (Blender's front view) -> Y up, +Z towards the viewer.
    rig_to_scene = glm::rotate(glm::mat4(1.0f), glm::radians(-90.0f), glm::vec3(1, 0, 0)) * rig_to_scene;
  }
  return rig_to_scene;
}

// The mean of the part's vertices (rig units): where blended parts sort.
glm::vec3 PartCentroid(const Rig& rig, const Part& part) {
  glm::vec3 sum(0.0f);
  for (std::uint32_t i = part.first_triangle; i < part.first_triangle + part.triangle_count; ++i) {
    for (std::uint32_t v : rig.triangles()[i]) sum += rig.positions()[v];
  }
  return part.triangle_count > 0 ? sum / (3.0f * static_cast<float>(part.triangle_count)) : sum;
}

// A per-vertex float that never changes, as attribute `location` of the
// bound vertex array; returns its buffer.
unsigned StaticFloatAttribute(unsigned location, std::span<const float> values) {
  unsigned vbo = 0;
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(values.size() * sizeof(float)), values.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(location, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);
  glEnableVertexAttribArray(location);
  return vbo;
}

// The bottom of the chin (scene space): the lowest of the vertices jawOpen
// moves most (the chin is the jaw's farthest point from its hinge); none
// without a jawOpen that moves something.
std::optional<glm::vec3> ChinBottom(const Rig& rig, const glm::mat4& rig_to_scene) {
  const std::vector<std::size_t> jaw = FindShapesByArkitName(rig, "jawOpen");
  if (jaw.empty()) return std::nullopt;
  const BlendShapeView shape = rig.shape(jaw.front());
  std::vector<std::pair<float, std::uint32_t>> moved;
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    moved.emplace_back(glm::length(shape.position_deltas[i]), shape.vertex_indices[i]);
  }
  if (moved.empty()) return std::nullopt;
  const std::size_t keep = std::clamp<std::size_t>(moved.size() / 50, 1, 200);
  std::partial_sort(moved.begin(), moved.begin() + static_cast<std::ptrdiff_t>(keep), moved.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  if (moved.front().first <= 0.0f) return std::nullopt;
  std::optional<glm::vec3> lowest;
  for (std::size_t i = 0; i < keep; ++i) {
    const glm::vec3 p = glm::vec3(rig_to_scene * glm::vec4(rig.positions()[moved[i].second], 1.0f));
    if (!lowest || p.y < lowest->y) lowest = p;
  }
  return lowest;
}

}  // namespace

struct FaceRenderer::DrawRange {
  std::uint32_t first_index = 0;
  std::uint32_t index_count = 0;
  PartLook look;
  unsigned base_texture = 0, normal_texture = 0;  // 0: none
  unsigned features = 0;                          // the shader variant (ShaderFeature bits)
  glm::vec3 centroid{0.0f};                       // rig units
  std::string name;
};

FaceRenderer::FaceRenderer(const Rig& rig) : vertex_count_(rig.vertex_count()), rig_to_scene_(RigToScene(rig)) {
  textures_ = std::make_unique<RigTextures>(rig);
  problems_ = textures_->problems();
  SetDrawRanges(rig);
  const std::vector<float> radial = IrisRadial(rig, rig_to_scene_, procedural_pupil_);
  const std::vector<float> mouth_light = MouthLight(rig, rig_to_scene_);
  FrameVisibleParts(rig);
  chin_ = ChinBottom(rig, rig_to_scene_);
  ResetCamera();
  CompileShaders();
  CreateBuffers(rig, radial, mouth_light);
}

void FaceRenderer::SetDrawRanges(const Rig& rig) {
  const bool has_uvs = !rig.uvs().empty();
  bool warned_uvs = false;
  for (const Part& part : rig.parts()) {
    DrawRange range{part.first_triangle * 3, part.triangle_count * 3, LookForPart(rig, part), 0, 0, 0,
                    PartCentroid(rig, part), part.name};
    if (range.index_count == 0 || !range.look.visible) continue;
    if (has_uvs) {
      range.base_texture = textures_->base_colour(range.look.base_colour_image);
      range.normal_texture = textures_->normal(range.look.normal_image);
    } else if (!warned_uvs && (range.look.base_colour_image >= 0 || range.look.normal_image >= 0)) {
      problems_.push_back("the rig's materials use images but it has no UVs; parts draw with their colour");
      warned_uvs = true;
    }
    range.features = (range.base_texture != 0 ? kBaseTexture : 0u) | (range.normal_texture != 0 ? kNormalTexture : 0u) |
                     (range.look.alpha_mode == AlphaMode::kMask ? kAlphaMask : 0u);
    ranges_.push_back(std::move(range));
  }
  // A rig without parts is all skin.
  if (ranges_.empty()) {
    Part all{"all", 0, static_cast<std::uint32_t>(rig.triangle_count())};
    ranges_.push_back({0, all.triangle_count * 3, LookForPart(rig, all), 0, 0, 0, PartCentroid(rig, all), "all"});
  }
  // Blended parts last, drawn after everything opaque.
  const auto blended = [](const DrawRange& r) { return r.look.alpha_mode == AlphaMode::kBlend; };
  first_blended_ = static_cast<std::size_t>(
      std::stable_partition(ranges_.begin(), ranges_.end(), [&](const DrawRange& r) { return !blended(r); }) -
      ranges_.begin());
  blend_order_.resize(ranges_.size() - first_blended_);
  const bool has_pupil = std::any_of(ranges_.begin(), ranges_.end(),
                                     [](const DrawRange& r) { return r.look.kind == Material::kPupil; });
  procedural_pupil_ = !has_pupil;
}

void FaceRenderer::FrameVisibleParts(const Rig& rig) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  const std::span<const glm::vec3> positions = rig.positions();
  for (const DrawRange& range : ranges_) {
    for (std::uint32_t i = range.first_index / 3; i < (range.first_index + range.index_count) / 3; ++i) {
      for (std::uint32_t v : rig.triangles()[i]) {
        const glm::vec3 p = glm::vec3(rig_to_scene_ * glm::vec4(positions[v], 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
    }
  }
  if (lo.x > hi.x) lo = hi = glm::vec3(0.0f);
  scene_center_ = (lo + hi) * 0.5f;
  scene_lo_ = lo;
  scene_hi_ = hi;
  scene_size_ = std::max(glm::length(hi - lo), 1e-6f);
  // The head turns about the top of the neck: below and behind the centre.
  neck_pivot_ = glm::vec3(scene_center_.x, glm::mix(lo.y, hi.y, 0.3f), glm::mix(lo.z, hi.z, 0.35f));
}

void FaceRenderer::CompileShaders() {
  variants_.resize(kShaderVariants);
  for (const DrawRange& range : ranges_) {
    ShaderVariant& variant = variants_[range.features];
    if (variant.program != 0) continue;
    const std::string vertex = FaceVertexShader(range.features), fragment = FaceFragmentShader(range.features);
    variant.program = CompileProgram(vertex.c_str(), fragment.c_str(), "face");
    const auto at = [&variant](const char* name) { return glGetUniformLocation(variant.program, name); };
    variant.u = {at("u_model"), at("u_view"), at("u_projection"), at("u_normal_matrix"), at("u_camera_position"),
                 at("u_material"), at("u_base_color"), at("u_procedural_pupil"), at("u_unlit"),
                 at("u_wrap"), at("u_shininess"), at("u_specular"), at("u_rim"), at("u_ambient"),
                 at("u_base_texture"), at("u_normal_texture"), at("u_alpha_mode"), at("u_alpha_cutoff")};
    glUseProgram(variant.program);
    glUniform1i(variant.u.base_texture, 0);
    glUniform1i(variant.u.normal_texture, 1);
  }
  glUseProgram(0);
}

void FaceRenderer::CreateBuffers(const Rig& rig, std::span<const float> radial, std::span<const float> mouth_light) {
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  const auto vertex_bytes = static_cast<GLsizeiptr>(vertex_count_ * sizeof(glm::vec3));
  glGenBuffers(1, &position_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glBufferData(GL_ARRAY_BUFFER, vertex_bytes, rig.positions().data(), GL_DYNAMIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &normal_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, normal_vbo_);
  glBufferData(GL_ARRAY_BUFFER, vertex_bytes, nullptr, GL_DYNAMIC_DRAW);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
  glEnableVertexAttribArray(1);
  radial_vbo_ = StaticFloatAttribute(2, radial);
  mouth_light_vbo_ = StaticFloatAttribute(4, mouth_light);
  CreateUvBuffer(rig);
  glGenBuffers(1, &ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(rig.triangle_count() * sizeof(Triangle)),
               rig.triangles().data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
}

// UVs never change: a static buffer, or (no UVs) the constant (0, 0).
void FaceRenderer::CreateUvBuffer(const Rig& rig) {
  if (rig.uvs().empty()) {
    glDisableVertexAttribArray(3);
    glVertexAttrib2f(3, 0.0f, 0.0f);
    return;
  }
  glGenBuffers(1, &uv_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, uv_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(rig.uvs().size() * sizeof(glm::vec2)), rig.uvs().data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glEnableVertexAttribArray(3);
}

FaceRenderer::~FaceRenderer() {
  if (uv_vbo_ != 0) glDeleteBuffers(1, &uv_vbo_);
  glDeleteBuffers(1, &position_vbo_);
  glDeleteBuffers(1, &normal_vbo_);
  glDeleteBuffers(1, &radial_vbo_);
  glDeleteBuffers(1, &mouth_light_vbo_);
  glDeleteBuffers(1, &ebo_);
  glDeleteVertexArrays(1, &vao_);
  for (const ShaderVariant& variant : variants_) {
    if (variant.program != 0) glDeleteProgram(variant.program);
  }
}

void FaceRenderer::ResetCamera() {
  camera_ = OrbitCamera{};
  // Frame the face, not the neck and shoulders: the upper part of the box.
  camera_.target = glm::vec3(scene_center_.x, glm::mix(scene_lo_.y, scene_hi_.y, 0.62f), scene_center_.z);
  const float half_fov = glm::radians(camera_.fov_degrees * 0.5f);
  const float frame_height = std::max(0.72f * (scene_hi_.y - scene_lo_.y), 1.1f * (scene_hi_.x - scene_lo_.x));
  camera_.distance = frame_height * 0.5f / std::tan(half_fov) + (scene_hi_.z - scene_lo_.z) * 0.5f;
  if (!chin_) return;
  // The whole face with its chin, and room below it for the jaw to open: a
  // head with a short neck framed by the upper part of its box lost its chin.
  // Where it would, the frame runs from the top of the head to below the chin
  // (the view's half height measured at the chin's depth, as perspective
  // shrinks what is nearer the camera).
  const float top = scene_hi_.y, span = top - chin_->y;
  const float bottom = chin_->y - 0.1f * span;
  const auto visible_below = [&] {
    const float half_at_chin = (camera_.distance - (chin_->z - camera_.target.z)) * std::tan(half_fov);
    return camera_.target.y - half_at_chin;
  };
  if (span <= 0.0f || visible_below() <= bottom) return;
  camera_.target.y = 0.5f * (top + 0.03f * span + bottom);
  const float half = 0.5f * (top + 0.03f * span - bottom);
  camera_.distance = half / std::tan(half_fov) + (chin_->z - camera_.target.z);
}

void FaceRenderer::Upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
  const auto bytes = static_cast<GLsizeiptr>(vertex_count_ * sizeof(glm::vec3));
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, positions.data());
  glBindBuffer(GL_ARRAY_BUFFER, normal_vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, normals.data());
}

glm::mat4 FaceRenderer::ModelMatrix(const glm::mat4& head_rotation) const {
  return glm::translate(glm::mat4(1.0f), neck_pivot_) * head_rotation *
         glm::translate(glm::mat4(1.0f), -neck_pivot_) * rig_to_scene_;
}

void FaceRenderer::SetFrameUniforms(const ShaderVariant& variant, int width, int height, const glm::mat4& model) {
  const Uniforms& u = variant.u;
  const glm::mat4 view = camera_.View();
  const glm::mat4 projection = camera_.Projection(static_cast<float>(width) / static_cast<float>(std::max(height, 1)));
  const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(model));
  const glm::vec3 camera_position = glm::vec3(glm::inverse(view)[3]);
  glUniformMatrix4fv(u.model, 1, GL_FALSE, glm::value_ptr(model));
  glUniformMatrix4fv(u.view, 1, GL_FALSE, glm::value_ptr(view));
  glUniformMatrix4fv(u.projection, 1, GL_FALSE, glm::value_ptr(projection));
  glUniformMatrix3fv(u.normal_matrix, 1, GL_FALSE, glm::value_ptr(normal_matrix));
  glUniform3fv(u.camera_position, 1, glm::value_ptr(camera_position));
  glUniform1i(u.procedural_pupil, procedural_pupil_ ? 1 : 0);
  glUniform1i(u.unlit, unlit_ ? 1 : 0);
}

void FaceRenderer::DrawRangeOf(const DrawRange& range, unsigned* current_variant) {
  if (range.features != *current_variant) {
    glUseProgram(variants_[range.features].program);
    *current_variant = range.features;
  }
  const Uniforms& u = variants_[range.features].u;
  const PartLook& look = range.look;
  // Named parts keep drawing both sides (the mouth interior is seen from inside).
  if (look.double_sided) {
    glDisable(GL_CULL_FACE);
  } else {
    glEnable(GL_CULL_FACE);
  }
  glUniform1i(u.material, static_cast<int>(look.kind));
  glUniform4fv(u.base_color, 1, glm::value_ptr(look.base_colour));
  glUniform3fv(u.wrap, 1, glm::value_ptr(look.shading.wrap));
  glUniform1f(u.shininess, look.shading.shininess);
  glUniform1f(u.specular, look.shading.specular);
  glUniform1f(u.rim, look.shading.rim);
  glUniform1f(u.ambient, look.shading.ambient);
  glUniform1i(u.alpha_mode, static_cast<int>(look.alpha_mode));
  glUniform1f(u.alpha_cutoff, look.alpha_cutoff);
  // Only textured variants sample: others leave the units alone.
  if (range.base_texture != 0) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, range.base_texture);
  }
  if (range.normal_texture != 0) {
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, range.normal_texture);
  }
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.index_count), GL_UNSIGNED_INT,
                 reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.first_index) * 4));
}

// Farthest first, by each part's centroid in view space (-z is away from the camera).
void FaceRenderer::SortBlendedBackToFront(const glm::mat4& model_view) {
  for (std::size_t i = first_blended_; i < ranges_.size(); ++i) {
    const float depth = (model_view * glm::vec4(ranges_[i].centroid, 1.0f)).z;
    blend_order_[i - first_blended_] = {depth, i};
  }
  std::sort(blend_order_.begin(), blend_order_.end());
}

void FaceRenderer::Draw(int width, int height, const glm::mat4& head_rotation) {
  glViewport(0, 0, width, height);
  glClearColor(0.16f, 0.18f, 0.21f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);

  const glm::mat4 model = ModelMatrix(head_rotation);
  for (const ShaderVariant& variant : variants_) {
    if (variant.program == 0) continue;
    glUseProgram(variant.program);
    SetFrameUniforms(variant, width, height, model);
  }
  glBindVertexArray(vao_);
  unsigned current_variant = kShaderVariants;  // none yet
  for (std::size_t i = 0; i < first_blended_; ++i) DrawRangeOf(ranges_[i], &current_variant);
  if (first_blended_ < ranges_.size()) {
    SortBlendedBackToFront(camera_.View() * model);
    glEnable(GL_BLEND);
    // Colour over what is behind; the target's alpha stays opaque.
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    for (const auto& [depth, index] : blend_order_) DrawRangeOf(ranges_[index], &current_variant);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  glDisable(GL_CULL_FACE);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(0);
}

glm::vec2 FaceRenderer::Project(const glm::vec3& rig_point, int width, int height,
                                const glm::mat4& head_rotation) const {
  const glm::mat4 mvp = camera_.Projection(static_cast<float>(width) / static_cast<float>(std::max(height, 1))) *
                        camera_.View() * ModelMatrix(head_rotation);
  const glm::vec4 clip = mvp * glm::vec4(rig_point, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {(ndc.x * 0.5f + 0.5f) * static_cast<float>(width),
          (0.5f - ndc.y * 0.5f) * static_cast<float>(height)};
}

}  // namespace facerig::player
