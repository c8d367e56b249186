#include "face_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "face_materials.h"
#include "face_shaders.h"
#include "iris_radial.h"

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

}  // namespace

FaceRenderer::FaceRenderer(const Rig& rig) : vertex_count_(rig.vertex_count()), rig_to_scene_(RigToScene(rig)) {
  SetDrawRanges(rig);
  const std::vector<float> radial = IrisRadial(rig, rig_to_scene_, procedural_pupil_);
  FrameVisibleParts(rig);
  ResetCamera();
  CompileShaders();
  CreateBuffers(rig, radial);
}

void FaceRenderer::SetDrawRanges(const Rig& rig) {
  // A rig without parts is all skin.
  for (const Part& part : rig.parts()) {
    DrawRange range{part.first_triangle * 3, part.triangle_count * 3, MaterialForPart(part.name), part.name};
    if (range.index_count > 0) ranges_.push_back(range);
  }
  if (ranges_.empty()) {
    ranges_.push_back({0, static_cast<std::uint32_t>(rig.triangle_count() * 3), Material::kSkin, "all"});
  }
  const bool has_pupil = std::any_of(ranges_.begin(), ranges_.end(),
                                     [](const DrawRange& r) { return r.material == Material::kPupil; });
  procedural_pupil_ = !has_pupil;
}

void FaceRenderer::FrameVisibleParts(const Rig& rig) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  const std::span<const glm::vec3> positions = rig.positions();
  for (const DrawRange& range : ranges_) {
    if (range.material == Material::kHidden) continue;
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
  program_ = CompileProgram(kFaceVertexShader, kFaceFragmentShader, "face");
  u_model_ = glGetUniformLocation(program_, "u_model");
  u_view_ = glGetUniformLocation(program_, "u_view");
  u_projection_ = glGetUniformLocation(program_, "u_projection");
  u_normal_matrix_ = glGetUniformLocation(program_, "u_normal_matrix");
  u_material_ = glGetUniformLocation(program_, "u_material");
  u_base_color_ = glGetUniformLocation(program_, "u_base_color");
  u_procedural_pupil_ = glGetUniformLocation(program_, "u_procedural_pupil");
  u_camera_position_ = glGetUniformLocation(program_, "u_camera_position");
}

void FaceRenderer::CreateBuffers(const Rig& rig, std::span<const float> radial) {
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
  glGenBuffers(1, &radial_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, radial_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(radial.size() * sizeof(float)), radial.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);
  glEnableVertexAttribArray(2);
  glGenBuffers(1, &ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(rig.triangle_count() * sizeof(Triangle)),
               rig.triangles().data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
}

FaceRenderer::~FaceRenderer() {
  glDeleteBuffers(1, &position_vbo_);
  glDeleteBuffers(1, &normal_vbo_);
  glDeleteBuffers(1, &radial_vbo_);
  glDeleteBuffers(1, &ebo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

void FaceRenderer::ResetCamera() {
  camera_ = OrbitCamera{};
  // Frame the face, not the neck and shoulders: the upper part of the box.
  camera_.target = glm::vec3(scene_center_.x, glm::mix(scene_lo_.y, scene_hi_.y, 0.62f), scene_center_.z);
  const float half_fov = glm::radians(camera_.fov_degrees * 0.5f);
  const float frame_height = std::max(0.72f * (scene_hi_.y - scene_lo_.y), 1.1f * (scene_hi_.x - scene_lo_.x));
  camera_.distance = frame_height * 0.5f / std::tan(half_fov) + (scene_hi_.z - scene_lo_.z) * 0.5f;
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

void FaceRenderer::Draw(int width, int height, const glm::mat4& head_rotation) {
  glViewport(0, 0, width, height);
  glClearColor(0.16f, 0.18f, 0.21f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);

  const glm::mat4 model = ModelMatrix(head_rotation);
  const glm::mat4 view = camera_.View();
  const glm::mat4 projection = camera_.Projection(static_cast<float>(width) / static_cast<float>(std::max(height, 1)));
  const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(model));
  const glm::vec3 camera_position = glm::vec3(glm::inverse(view)[3]);

  glUseProgram(program_);
  glUniformMatrix4fv(u_model_, 1, GL_FALSE, glm::value_ptr(model));
  glUniformMatrix4fv(u_view_, 1, GL_FALSE, glm::value_ptr(view));
  glUniformMatrix4fv(u_projection_, 1, GL_FALSE, glm::value_ptr(projection));
  glUniformMatrix3fv(u_normal_matrix_, 1, GL_FALSE, glm::value_ptr(normal_matrix));
  glUniform3fv(u_camera_position_, 1, glm::value_ptr(camera_position));
  glUniform1i(u_procedural_pupil_, procedural_pupil_ ? 1 : 0);
  glBindVertexArray(vao_);
  for (const DrawRange& range : ranges_) {
    if (range.material == Material::kHidden) continue;
    glUniform1i(u_material_, static_cast<int>(range.material));
    const glm::vec3 color = BaseColor(range.material);
    glUniform3fv(u_base_color_, 1, glm::value_ptr(color));
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.index_count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.first_index) * 4));
  }
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
