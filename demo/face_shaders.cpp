#include "face_shaders.h"

namespace facerig::player {

const char* const kFaceVertexShader = R"(#version 330 core
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
const char* const kFaceFragmentShader = R"(#version 330 core
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

}  // namespace facerig::player
