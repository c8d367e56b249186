#include "face_renderer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace facerig::player {
namespace {

const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_radial;
uniform mat4 u_model, u_view, u_projection;
uniform mat3 u_normal_matrix;
out vec3 v_world;
out vec3 v_normal;
out float v_radial;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_radial = a_radial;
  gl_Position = u_projection * u_view * world;
}
)";

// Lighting in world space (Y up, face towards +Z): a warm key light from the
// upper left, a cool fill from the right, a back light for the rim, and a
// sky/ground ambient.
// Skin: per-channel wrap lighting (red scatters furthest under the skin, so
// the terminator turns warm instead of grey: a cheap subsurface look), a
// broad soft specular with Fresnel, and a rim.
// Eyes: a glossy sclera; the iris darkens towards the limbus and, on rigs
// without a pupil mesh (ICT-FaceKit), draws its pupil from the vertex's
// normalised distance to the iris centre (a_radial).
const char* const kFragmentShader = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in float v_radial;
uniform int u_material;
uniform vec3 u_base_color;
uniform bool u_procedural_pupil;
uniform vec3 u_camera_position;
out vec4 frag_color;

const int kSkin = 0, kSclera = 1, kIris = 2, kPupil = 3, kTeeth = 4, kGums = 5, kTongue = 6,
          kMouthInner = 7;

vec3 KeyDir() { return normalize(vec3(-0.75, 0.6, 0.6)); }
vec3 FillDir() { return normalize(vec3(0.9, 0.0, 0.5)); }
vec3 RimDir() { return normalize(vec3(0.3, 0.5, -0.9)); }
const vec3 kKeyColor = vec3(1.00, 0.93, 0.84) * 2.2;
const vec3 kFillColor = vec3(0.55, 0.65, 0.85) * 0.5;
const vec3 kRimColor = vec3(0.85, 0.9, 1.0) * 1.6;

vec3 WrapDiffuse(vec3 n, vec3 l, vec3 wrap) {
  float ndl = dot(n, l);
  return clamp((vec3(ndl) + wrap) / (1.0 + wrap), 0.0, 1.0);
}

float Specular(vec3 n, vec3 l, vec3 v, float shininess) {
  vec3 h = normalize(l + v);
  float ndh = max(dot(n, h), 0.0);
  // Normalised Blinn-Phong so a broad highlight is dimmer than a sharp one.
  return pow(ndh, shininess) * (shininess + 8.0) / 25.0 * step(0.0, dot(n, l));
}

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // inner mouth and single-sided parts are seen from both sides
  vec3 v = normalize(u_camera_position - v_world);
  float ndv = max(dot(n, v), 0.0);
  vec3 base = u_base_color;
  vec3 wrap = vec3(0.0);
  float shininess = 16.0, spec_strength = 0.04, rim_strength = 0.0, ambient_scale = 1.0;

  if (u_material == kSkin) {
    wrap = vec3(0.55, 0.25, 0.18);
    shininess = 24.0; spec_strength = 0.05; rim_strength = 0.35;
  } else if (u_material == kSclera || u_material == kIris) {
    float r = v_radial;
    bool iris = u_material == kIris || (u_procedural_pupil && r >= 0.0 && r < 1.0);
    if (iris) {
      if (u_procedural_pupil && r >= 0.0 && r < 0.42) {
        base = vec3(0.008);
      } else {
        vec3 iris_color = u_material == kIris ? base : vec3(0.07, 0.17, 0.26);
        float limbus = smoothstep(0.7, 1.0, r);
        float fibres = 0.8 + 0.2 * sin(r * 55.0);
        base = iris_color * fibres * mix(1.0, 0.3, limbus);
      }
    } else {
      // The sclera darkens towards the corners and where the lids shade it.
      base *= mix(0.55, 1.0, ndv);
    }
    wrap = vec3(0.15);
    shininess = 500.0; spec_strength = 0.9;
  } else if (u_material == kPupil) {
    shininess = 400.0; spec_strength = 0.8;
  } else if (u_material == kTeeth) {
    wrap = vec3(0.3, 0.28, 0.25);
    shininess = 60.0; spec_strength = 0.15; ambient_scale = 0.7;
  } else if (u_material == kGums || u_material == kTongue) {
    wrap = vec3(0.5, 0.25, 0.2);
    shininess = 40.0; spec_strength = 0.12; ambient_scale = 0.5;
  } else if (u_material == kMouthInner) {
    ambient_scale = 0.3; spec_strength = 0.02;
  }

  vec3 key = WrapDiffuse(n, KeyDir(), wrap) * kKeyColor;
  vec3 fill = WrapDiffuse(n, FillDir(), wrap) * kFillColor;
  float up = n.y * 0.5 + 0.5;
  vec3 ambient = mix(vec3(0.06, 0.045, 0.04), vec3(0.13, 0.14, 0.17), up) * ambient_scale;
  vec3 color = base * (key + fill + ambient);

  float fresnel = 0.04 + 0.96 * pow(1.0 - ndv, 5.0);
  color += kKeyColor * Specular(n, KeyDir(), v, shininess) * spec_strength * (1.0 + 4.0 * fresnel);
  color += kFillColor * Specular(n, FillDir(), v, shininess) * spec_strength;
  if (rim_strength > 0.0) {
    float rim = pow(1.0 - ndv, 3.0) * max(dot(n, RimDir()) + 0.3, 0.0);
    color += kRimColor * rim * rim_strength * base;
  }
  // Reinhard-style shoulder so the lit cheek does not clip, then gamma.
  color = color / (1.0 + 0.35 * color) * 1.1;
  frag_color = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

glm::vec3 BaseColor(Material material) {
  switch (material) {
    // Linear colours (the shader outputs gamma 2.2).
    case Material::kSkin: return {0.54f, 0.33f, 0.245f};
    case Material::kSclera: return {0.72f, 0.69f, 0.66f};
    case Material::kIris: return {0.07f, 0.17f, 0.26f};
    case Material::kPupil: return {0.008f, 0.008f, 0.01f};
    case Material::kTeeth: return {0.66f, 0.62f, 0.52f};
    case Material::kGums: return {0.42f, 0.09f, 0.09f};
    case Material::kTongue: return {0.45f, 0.11f, 0.12f};
    case Material::kMouthInner: return {0.10f, 0.02f, 0.02f};
    case Material::kHidden: break;
  }
  return {0.0f, 0.0f, 0.0f};
}

std::string Lower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

}  // namespace

Material MaterialForPart(std::string_view part_name) {
  const std::string name = Lower(part_name);
  const auto has = [&](const char* word) { return name.find(word) != std::string::npos; };
  if (has("occlusion") || has("lacrimal") || has("eyeblend")) return Material::kHidden;
  if (has("lash")) return Material::kHidden;
  if (has("sclera") || has("eye_white") || has("eyewhite")) return Material::kSclera;
  if (has("pupil")) return Material::kPupil;
  if (has("iris")) return Material::kIris;
  if (has("teeth") || has("tooth")) return Material::kTeeth;
  if (has("gum")) return Material::kGums;
  if (has("tongue")) return Material::kTongue;
  if (has("mouth_inner") || has("mouthinner") || has("mouth_cavity")) return Material::kMouthInner;
  return Material::kSkin;
}

const char* ToString(Material material) {
  switch (material) {
    case Material::kSkin: return "skin";
    case Material::kSclera: return "sclera";
    case Material::kIris: return "iris";
    case Material::kPupil: return "pupil";
    case Material::kTeeth: return "teeth";
    case Material::kGums: return "gums";
    case Material::kTongue: return "tongue";
    case Material::kMouthInner: return "mouth inner";
    case Material::kHidden: return "hidden";
  }
  return "?";
}

void OrbitCamera::Orbit(float dx_degrees, float dy_degrees) {
  yaw_degrees += dx_degrees;
  pitch_degrees = std::clamp(pitch_degrees + dy_degrees, -80.0f, 80.0f);
}

void OrbitCamera::Zoom(float steps) { distance *= std::pow(0.9f, steps); }

glm::mat4 OrbitCamera::View() const {
  const float yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
  const glm::vec3 direction(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                            std::cos(yaw) * std::cos(pitch));
  return glm::lookAt(target + direction * distance, target, glm::vec3(0, 1, 0));
}

glm::mat4 OrbitCamera::Projection(float aspect) const {
  return glm::perspective(glm::radians(fov_degrees), aspect, distance * 0.05f, distance * 20.0f);
}

unsigned CompileProgram(const char* vertex_source, const char* fragment_source, const char* name) {
  const auto compile = [&](GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
      glDeleteShader(shader);
      throw std::runtime_error(std::string(name) + " shader: " + log);
    }
    return shader;
  };
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
  const GLuint fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof(log), nullptr, log);
    glDeleteProgram(program);
    throw std::runtime_error(std::string(name) + " program: " + log);
  }
  return program;
}

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

// The vertices of the part's triangles, sorted, each once.
std::vector<std::uint32_t> PartVertices(const Rig& rig, const Part& part) {
  std::vector<std::uint32_t> vertices;
  for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
    for (std::uint32_t v : rig.triangles()[t]) vertices.push_back(v);
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

// A sclera that carries the iris: the angle from the eyeball's forward axis
// over the iris's angular radius.
void SetScleraRadial(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& vertices,
                     const glm::vec3& center, const glm::vec3& forward, std::vector<float>* radial) {
  constexpr float kIrisHalfAngle = 0.52f;  // a 12 mm iris on a 24 mm eyeball
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    const float length = glm::length(d);
    const float angle = length > 0.0f ? std::acos(std::clamp(glm::dot(d / length, forward), -1.0f, 1.0f)) : 3.0f;
    (*radial)[v] = angle / kIrisHalfAngle;
  }
}

// An iris mesh: distance across the forward axis over the part's radius
// (a domed iris works too).
void SetIrisRadial(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& vertices,
                   const glm::vec3& center, const glm::vec3& forward, std::vector<float>* radial) {
  float max_distance = 0.0f;
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    max_distance = std::max(max_distance, glm::length(d - forward * glm::dot(d, forward)));
  }
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    (*radial)[v] = max_distance > 0.0f ? glm::length(d - forward * glm::dot(d, forward)) / max_distance : 0.0f;
  }
}

// The iris shading reads a_radial: 0 at the iris centre, 1 at its rim
// (-1: not an eye vertex). For rigs without a pupil mesh (ICT-FaceKit),
// whose opaque sclera covers the iris mesh, the sclera itself carries the
// iris. It is attached to the vertices, so it follows eyeLook* shapes.
std::vector<float> IrisRadial(const Rig& rig, const glm::mat4& rig_to_scene, bool procedural_pupil) {
  std::vector<float> radial(rig.vertex_count(), -1.0f);
  const std::span<const glm::vec3> positions = rig.positions();
  const glm::vec3 forward = glm::normalize(glm::vec3(glm::inverse(rig_to_scene) * glm::vec4(0, 0, 1, 0)));
  for (const Part& part : rig.parts()) {
    const Material material = MaterialForPart(part.name);
    if (material != Material::kIris && !(material == Material::kSclera && procedural_pupil)) continue;
    const std::vector<std::uint32_t> vertices = PartVertices(rig, part);
    if (vertices.empty()) continue;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::uint32_t v : vertices) {
      lo = glm::min(lo, positions[v]);
      hi = glm::max(hi, positions[v]);
    }
    const glm::vec3 center = (lo + hi) * 0.5f;
    if (material == Material::kSclera) {
      SetScleraRadial(positions, vertices, center, forward, &radial);
    } else {
      SetIrisRadial(positions, vertices, center, forward, &radial);
    }
  }
  return radial;
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
  program_ = CompileProgram(kVertexShader, kFragmentShader, "face");
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

OffscreenTarget::OffscreenTarget(int width, int height, int samples) : width_(width), height_(height) {
  glGenFramebuffers(1, &msaa_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
  glGenRenderbuffers(1, &msaa_color_);
  glBindRenderbuffer(GL_RENDERBUFFER, msaa_color_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color_);
  glGenRenderbuffers(1, &msaa_depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, msaa_depth_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("offscreen framebuffer (" + std::to_string(samples) + "x MSAA) is incomplete");
  }
  glGenFramebuffers(1, &resolve_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
  glGenRenderbuffers(1, &resolve_color_);
  glBindRenderbuffer(GL_RENDERBUFFER, resolve_color_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("offscreen resolve framebuffer is incomplete");
  }
}

OffscreenTarget::~OffscreenTarget() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteRenderbuffers(1, &msaa_color_);
  glDeleteRenderbuffers(1, &msaa_depth_);
  glDeleteRenderbuffers(1, &resolve_color_);
  glDeleteFramebuffers(1, &msaa_fbo_);
  glDeleteFramebuffers(1, &resolve_fbo_);
}

void OffscreenTarget::Bind() { glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_); }

void OffscreenTarget::Read(Image* image) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  image->width = width_;
  image->height = height_;
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  image->rgba.resize(row * static_cast<std::size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image->rgba.data());
  // GL rows go bottom to top.
  std::vector<std::uint8_t> swap(row);
  for (int y = 0; y < height_ / 2; ++y) {
    std::uint8_t* a = image->rgba.data() + static_cast<std::size_t>(y) * row;
    std::uint8_t* b = image->rgba.data() + static_cast<std::size_t>(height_ - 1 - y) * row;
    std::copy(a, a + row, swap.data());
    std::copy(b, b + row, a);
    std::copy(swap.data(), swap.data() + row, b);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
}

}  // namespace facerig::player
