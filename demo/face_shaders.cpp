#include "face_shaders.h"

#include <string>

namespace facerig::player {

const char* const kFaceVertexBody = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_radial;
layout(location = 4) in float a_mouth_light;
#ifdef UVS
layout(location = 3) in vec2 a_uv;
out vec2 v_uv;
#endif
uniform mat4 u_model, u_view, u_projection;
uniform mat3 u_normal_matrix;
out vec3 v_world;
out vec3 v_normal;
out float v_radial;
out float v_mouth_light;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_radial = a_radial;
  v_mouth_light = a_mouth_light;
#ifdef UVS
  v_uv = a_uv;
#endif
  gl_Position = u_projection * u_view * world;
}
)";

// Lighting in linear space, in world space (Y up, face towards +Z): a warm key
// light from the upper left, a cool fill from the right, a back light for the
// rim, and a sky/ground ambient; the result is tone mapped and encoded sRGB.
// Base colour = factor x texture (sRGB textures sample linear). The shading
// uniforms (face_materials.h) carry each part's response:
// - per-channel wrap diffuse: red wraps furthest past the terminator, so skin
//   turns warm there instead of grey (a cheap subsurface look);
// - normalised Blinn-Phong specular with Fresnel (the exponent comes from the
//   material's roughness): sharp and bright on eyes, broad and dim on skin;
// - ambient < 1 inside the mouth (occluded).
// Eyes without a texture: the iris darkens towards the limbus and, on rigs
// without a pupil mesh (ICT-FaceKit), draws its pupil from the vertex's
// normalised distance to the iris centre (a_radial).
// Normal maps: the tangent frame comes from screen-space derivatives of the
// position and UV (no tangent attribute); green points towards +v (OpenGL's
// and glTF's convention).
// Textures and alpha masking are compiled in only where a part needs them: a
// shader that can discard loses early depth testing, and on llvmpipe unused
// texture paths still cost.
const char* const kFaceFragmentBody = R"(
in vec3 v_world;
in vec3 v_normal;
in float v_radial;
in float v_mouth_light;  // light reaching the inside of the mouth (mouth_light.h)
#ifdef UVS
in vec2 v_uv;
#endif
uniform int u_material;
uniform vec4 u_base_color;
uniform bool u_procedural_pupil;
uniform vec3 u_camera_position;
uniform vec3 u_wrap;
uniform float u_shininess, u_specular, u_rim, u_ambient;
#ifdef BASE_TEXTURE
uniform sampler2D u_base_texture;
#endif
#ifdef NORMAL_TEXTURE
uniform sampler2D u_normal_texture;
#endif
uniform int u_alpha_mode;
uniform float u_alpha_cutoff;
uniform bool u_unlit;
out vec4 frag_color;

const int kSkin = 0, kSclera = 1, kIris = 2, kPupil = 3, kTeeth = 4, kGums = 5, kTongue = 6,
          kMouthInner = 7;
const int kBlend = 2;

vec3 KeyDir() { return normalize(vec3(-0.75, 0.6, 0.6)); }
vec3 FillDir() { return normalize(vec3(0.9, 0.0, 0.5)); }
vec3 RimDir() { return normalize(vec3(0.3, 0.5, -0.9)); }
const vec3 kKeyColor = vec3(1.00, 0.93, 0.84) * 2.2;
const vec3 kFillColor = vec3(0.55, 0.65, 0.85) * 0.5;
const vec3 kRimColor = vec3(0.85, 0.9, 1.0) * 1.6;

#ifdef UVS
// The rig's UVs have v up from the image's bottom; textures hold row 0 (the top) at t = 0.
vec2 TexCoord() { return vec2(v_uv.x, 1.0 - v_uv.y); }
#endif

vec3 EncodeSrgb(vec3 linear) {
  vec3 c = clamp(linear, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

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

#ifdef NORMAL_TEXTURE
vec3 PerturbedNormal(vec3 n) {
  vec3 dp1 = dFdx(v_world), dp2 = dFdy(v_world);
  vec2 duv1 = dFdx(v_uv), duv2 = dFdy(v_uv);
  vec3 dp2perp = cross(dp2, n), dp1perp = cross(n, dp1);
  vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
  vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
  float len2 = max(dot(t, t), dot(b, b));
  if (len2 <= 0.0) return n;  // UVs constant over the pixel: no frame
  float s = inversesqrt(len2);
  vec3 m = texture(u_normal_texture, TexCoord()).xyz * 2.0 - 1.0;
  return normalize(mat3(t * s, b * s, n) * m);
}
#endif

// Untextured eyes: iris fibres, a darker limbus, the procedural pupil, a
// sclera that darkens towards the corners.
vec3 EyeColor(vec3 base, float ndv) {
  float r = v_radial;
  bool iris = u_material == kIris || (u_procedural_pupil && r >= 0.0 && r < 1.0);
  if (!iris) return base * mix(0.55, 1.0, ndv);
  if (u_procedural_pupil && r >= 0.0 && r < 0.42) return vec3(0.008);
  vec3 iris_color = u_material == kIris ? base : vec3(0.07, 0.17, 0.26);
  float limbus = smoothstep(0.7, 1.0, r);
  float fibres = 0.8 + 0.2 * sin(r * 55.0);
  return iris_color * fibres * mix(1.0, 0.3, limbus);
}

void main() {
  vec4 base = u_base_color;
#ifdef BASE_TEXTURE
  base *= texture(u_base_texture, TexCoord());
#endif
#ifdef ALPHA_MASK
  if (base.a < u_alpha_cutoff) discard;
#endif
  float alpha = u_alpha_mode == kBlend ? base.a : 1.0;
  if (u_unlit) {
    frag_color = vec4(EncodeSrgb(base.rgb), alpha);
    return;
  }
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;  // inner mouth and single-sided parts are seen from both sides
#ifdef NORMAL_TEXTURE
  n = PerturbedNormal(n);
#endif
  vec3 v = normalize(u_camera_position - v_world);
  float ndv = max(dot(n, v), 0.0);
  vec3 albedo = base.rgb;
#ifndef BASE_TEXTURE
  if (u_material == kSclera || u_material == kIris) albedo = EyeColor(albedo, ndv);
#endif

  vec3 key = WrapDiffuse(n, KeyDir(), u_wrap) * kKeyColor;
  vec3 fill = WrapDiffuse(n, FillDir(), u_wrap) * kFillColor;
  float up = n.y * 0.5 + 0.5;
  vec3 ambient = mix(vec3(0.06, 0.045, 0.04), vec3(0.13, 0.14, 0.17), up) * u_ambient;
  vec3 color = albedo * (key + fill + ambient) * v_mouth_light;

  float fresnel = 0.04 + 0.96 * pow(1.0 - ndv, 5.0);
  float specular_light = u_specular * v_mouth_light;
  color += kKeyColor * Specular(n, KeyDir(), v, u_shininess) * specular_light * (1.0 + 4.0 * fresnel);
  color += kFillColor * Specular(n, FillDir(), v, u_shininess) * specular_light;
  if (u_rim > 0.0) {
    float rim = pow(1.0 - ndv, 3.0) * max(dot(n, RimDir()) + 0.3, 0.0);
    color += kRimColor * rim * u_rim * albedo;
  }
  // Reinhard-style shoulder so the lit cheek does not clip.
  color = color / (1.0 + 0.35 * color) * 1.1;
  frag_color = vec4(EncodeSrgb(color), alpha);
}
)";

namespace {

std::string Header(unsigned features) {
  std::string header = "#version 330 core\n";
  if (features & (kBaseTexture | kNormalTexture)) header += "#define UVS\n";
  return header;
}

}  // namespace

std::string FaceVertexShader(unsigned features) { return Header(features) + kFaceVertexBody; }

std::string FaceFragmentShader(unsigned features) {
  std::string source = Header(features);
  if (features & kBaseTexture) source += "#define BASE_TEXTURE\n";
  if (features & kNormalTexture) source += "#define NORMAL_TEXTURE\n";
  if (features & kAlphaMask) source += "#define ALPHA_MASK\n";
  return source + kFaceFragmentBody;
}

}  // namespace facerig::player
