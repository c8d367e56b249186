#include "facerig/offline/render/eye_textures.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/render/png_encode.h"
#include "facerig/runtime/part_roles.h"
#include "render/srgb.h"
#include "render/uv_raster.h"
#include "geometry/smooth_step.h"
#include "geometry/bounding_box.h"
#include "render/unit_byte.h"

namespace facerig {
namespace {

// Linear RGB.
const glm::vec3 kSclera{0.80f, 0.76f, 0.72f};
const glm::vec3 kIrisOuter{0.045f, 0.12f, 0.21f};
const glm::vec3 kIrisInner{0.13f, 0.16f, 0.12f};  // a warmer ring round the pupil
const glm::vec3 kPupil{0.008f, 0.008f, 0.01f};
const glm::vec3 kLash{0.015f, 0.011f, 0.008f};

// One eye part and the frame its pattern is laid out in.
struct EyeFrame {
  glm::vec3 centre{0.0f};   // the eyeball's centre
  glm::vec3 forward{0.0f, 0.0f, 1.0f};
  glm::vec3 side{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
  bool on_eyeball = true;   // radial from the angle to forward; else across it
  float across_radius = 1.0f;  // an iris mesh's largest distance across forward
  float radius = 1.0f;         // an eyeball's (median distance from its centre)
  bool carries_iris = true;
  bool carries_pupil = true;
};

std::vector<std::vector<std::uint32_t>> VerticesOfParts(const Mesh& mesh) {
  std::vector<std::vector<std::uint32_t>> vertices(mesh.part_names.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    for (std::uint32_t v : mesh.triangles[t]) vertices[mesh.triangle_parts[t]].push_back(v);
  }
  for (auto& list : vertices) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return vertices;
}

glm::vec3 BoxCentre(const Mesh& mesh, const std::vector<std::uint32_t>& vertices) {
  return BoxAround(mesh.positions, vertices).centre();
}

float MedianDistance(const Mesh& mesh, const std::vector<std::uint32_t>& vertices, const glm::vec3& centre) {
  std::vector<float> distances;
  for (std::uint32_t v : vertices) distances.push_back(glm::length(mesh.positions[v] - centre));
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  return distances[distances.size() / 2];
}

float BoxRadius(const Mesh& mesh, const std::vector<std::uint32_t>& vertices, const glm::vec3& centre) {
  float radius = 0.0f;
  for (std::uint32_t v : vertices) radius = std::max(radius, glm::length(mesh.positions[v] - centre));
  return radius;
}

void SetAxes(EyeFrame& frame, const glm::vec3& forward) {
  frame.forward = forward;
  const glm::vec3 helper = std::abs(forward.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  frame.side = glm::normalize(glm::cross(helper, forward));
  frame.up = glm::cross(forward, frame.side);
}

// The iris part nearest `centre` within `radius`, or -1.
int NearestPart(const std::vector<glm::vec3>& centres, const std::vector<int>& parts, const glm::vec3& centre,
                float radius) {
  int best = -1;
  float best_distance = radius;
  for (int part : parts) {
    const float distance = glm::length(centres[static_cast<std::size_t>(part)] - centre);
    if (distance <= best_distance) best = part, best_distance = distance;
  }
  return best;
}

// Where an eyeball's cornea bulges out of its sphere: from the centre to the
// mean of its farthest vertices, when they stand out by more than 5% of its
// radius; else zero (a plain sphere says nothing of where it looks).
glm::vec3 CorneaDirection(const Mesh& mesh, const std::vector<std::uint32_t>& vertices, const glm::vec3& centre) {
  std::vector<float> distances;
  for (std::uint32_t v : vertices) distances.push_back(glm::length(mesh.positions[v] - centre));
  const float median = MedianDistance(mesh, vertices, centre);
  const float farthest = *std::max_element(distances.begin(), distances.end());
  if (!(farthest > 1.05f * median)) return glm::vec3(0.0f);
  glm::vec3 sum(0.0f);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (distances[i] > 0.5f * (median + farthest)) sum += mesh.positions[vertices[i]] - centre;
  }
  return glm::length(sum) > 0.0f ? glm::normalize(sum) : glm::vec3(0.0f);
}

// An eyeball's forward axis: towards the iris mesh inside it where that lies
// off its centre, else towards its cornea, else +Z (glTF's forward).
glm::vec3 EyeballForward(const Mesh& mesh, const std::vector<std::uint32_t>& vertices, const glm::vec3& centre,
                         float radius, const glm::vec3* iris_centre) {
  if (iris_centre != nullptr && glm::length(*iris_centre - centre) > 0.1f * radius) {
    return glm::normalize(*iris_centre - centre);
  }
  const glm::vec3 cornea = CorneaDirection(mesh, vertices, centre);
  return glm::length(cornea) > 0.0f ? cornea : glm::vec3(0.0f, 0.0f, 1.0f);
}

// Each eye part's frame (EyeballForward). An iris mesh is centred on the
// eyeball around it (else on itself); one as large as its eyeball (a second
// ball under the sclera) is painted as an eyeball.
std::map<std::uint32_t, EyeFrame> EyeFrames(const Mesh& mesh, const std::vector<std::vector<std::uint32_t>>& vertices) {
  std::vector<PartRole> roles(mesh.part_names.size());
  std::vector<glm::vec3> centres(mesh.part_names.size());
  std::vector<float> radii(mesh.part_names.size());
  std::vector<int> scleras, irises;
  bool has_pupil = false;
  for (std::size_t p = 0; p < roles.size(); ++p) {
    roles[p] = RoleOfPart(mesh.part_names[p]);
    if (vertices[p].empty()) continue;
    centres[p] = BoxCentre(mesh, vertices[p]);
    radii[p] = BoxRadius(mesh, vertices[p], centres[p]);
    if (roles[p] == PartRole::kSclera) scleras.push_back(static_cast<int>(p));
    if (roles[p] == PartRole::kIris) irises.push_back(static_cast<int>(p));
    has_pupil = has_pupil || roles[p] == PartRole::kPupil;
  }
  std::map<std::uint32_t, EyeFrame> frames;
  for (int sclera : scleras) {
    const auto s = static_cast<std::size_t>(sclera);
    EyeFrame& frame = frames[static_cast<std::uint32_t>(s)];
    frame.centre = centres[s];
    frame.radius = MedianDistance(mesh, vertices[s], centres[s]);
    const int iris = NearestPart(centres, irises, centres[s], radii[s]);
    const glm::vec3* iris_centre = iris >= 0 ? &centres[static_cast<std::size_t>(iris)] : nullptr;
    SetAxes(frame, EyeballForward(mesh, vertices[s], centres[s], radii[s], iris_centre));
    frame.carries_iris = frame.carries_pupil = !has_pupil;
  }
  for (int iris : irises) {
    const auto i = static_cast<std::size_t>(iris);
    const int sclera = NearestPart(centres, scleras, centres[i], std::numeric_limits<float>::max());
    const bool inside = sclera >= 0 && glm::length(centres[i] - centres[static_cast<std::size_t>(sclera)]) <=
                                           radii[static_cast<std::size_t>(sclera)];
    EyeFrame frame = inside ? frames[static_cast<std::uint32_t>(sclera)] : EyeFrame{.centre = centres[i]};
    frame.on_eyeball = inside && radii[i] > 0.5f * radii[static_cast<std::size_t>(sclera)];
    frame.carries_iris = true;
    frame.carries_pupil = !has_pupil;
    float across = 0.0f;
    for (std::uint32_t v : vertices[i]) {
      const glm::vec3 d = mesh.positions[v] - frame.centre;
      across = std::max(across, glm::length(d - frame.forward * glm::dot(d, frame.forward)));
    }
    frame.across_radius = across > 0.0f ? across : 1.0f;
    frames[static_cast<std::uint32_t>(i)] = frame;
  }
  return frames;
}

glm::vec3 Mix(const glm::vec3& a, const glm::vec3& b, float t) { return a + (b - a) * t; }

// The colour at radial distance r (0: the iris's centre, 1: its rim) and
// azimuth a (radians round the forward axis).
glm::vec3 EyeColour(const EyeFrame& frame, const EyeTextureParams& params, float r, float a) {
  // The sclera shades a little towards the corners of the eye, where it
  // turns away from the light.
  const glm::vec3 sclera = kSclera * (1.0f - 0.2f * SmoothStep(1.6f, 3.5f, r));
  if (!frame.carries_iris) return sclera;
  const float fibres = 0.75f + 0.25f * (0.5f + 0.5f * std::sin(23.0f * a + 3.0f * std::sin(7.0f * a)));
  glm::vec3 iris = Mix(kIrisInner, kIrisOuter, SmoothStep(0.45f, 0.75f, r)) * fibres;
  iris *= 1.0f - 0.65f * SmoothStep(0.8f, 1.0f, r);  // the limbal ring
  glm::vec3 colour = Mix(iris, sclera, SmoothStep(1.0f, 1.08f, r));
  if (frame.carries_pupil) {
    colour = Mix(kPupil, colour, SmoothStep(params.pupil_fraction - 0.03f, params.pupil_fraction + 0.03f, r));
  }
  return colour;
}

glm::vec3 ColourAt(const EyeFrame& frame, const EyeTextureParams& params, const glm::vec3& p) {
  const glm::vec3 d = p - frame.centre;
  const float along = glm::dot(d, frame.forward);
  const glm::vec3 across = d - frame.forward * along;
  const float a = std::atan2(glm::dot(across, frame.up), glm::dot(across, frame.side));
  float r = glm::length(across) / frame.across_radius;
  if (frame.on_eyeball) {
    const float length = glm::length(d);
    r = length > 0.0f ? std::acos(std::clamp(along / length, -1.0f, 1.0f)) / params.iris_half_angle : 0.0f;
  }
  return EyeColour(frame, params, r, a);
}

// Eyelashes: dark hairs fanning out from the lid round the nearest eye's
// forward axis (lines of constant azimuth), thinning towards their tips; the
// rest transparent.
glm::vec4 LashColour(const EyeFrame& eye, float root, float tip, const glm::vec3& p) {
  const glm::vec3 d = p - eye.centre;
  const glm::vec3 across = d - eye.forward * glm::dot(d, eye.forward);
  const float a = std::atan2(glm::dot(across, eye.up), glm::dot(across, eye.side));
  const float t = std::clamp((glm::length(d) - root) / std::max(tip - root, 1e-6f), 0.0f, 1.0f);
  const float wobble = 0.6f * std::sin(37.0f * a) + 0.4f * std::sin(91.0f * a);
  const float hair = SmoothStep(0.55f, 0.85f, 0.5f + 0.5f * std::cos(240.0f * a + 2.0f * wobble + 6.0f * t));
  // Lower lashes are fewer, fainter and shorter than upper ones.
  const bool lower = glm::dot(across, eye.up) < 0.0f;
  const float length = lower ? 0.5f : 1.0f;
  const float alpha = std::max(hair * (1.0f - SmoothStep(0.35f * length, length, t)), 1.0f - SmoothStep(0.0f, 0.12f, t));
  return {kLash, (lower ? 0.45f : 0.9f) * alpha};
}

// What a part's texels show, by their surface point (linear RGBA).
using Painter = std::function<glm::vec4(const glm::vec3&)>;

// A lash part's painter: each point takes the nearest eyeball's hairs; the
// root and tip distances from that eyeball's centre are the lash part's own.
Painter LashPainter(const Mesh& mesh, const std::vector<std::uint32_t>& vertices, std::vector<EyeFrame> eyes) {
  const auto nearest = [eyes](const glm::vec3& p) {
    std::size_t best = 0;
    for (std::size_t e = 1; e < eyes.size(); ++e) {
      if (glm::length(p - eyes[e].centre) < glm::length(p - eyes[best].centre)) best = e;
    }
    return best;
  };
  std::vector<float> root(eyes.size(), std::numeric_limits<float>::max()), tip(eyes.size(), 0.0f);
  for (std::uint32_t v : vertices) {
    const std::size_t e = nearest(mesh.positions[v]);
    const float distance = glm::length(mesh.positions[v] - eyes[e].centre);
    root[e] = std::min(root[e], distance);
    tip[e] = std::max(tip[e], distance);
  }
  return [eyes, nearest, root, tip](const glm::vec3& p) {
    const std::size_t e = nearest(p);
    return LashColour(eyes[e], root[e], tip[e], p);
  };
}

// A painter for each eye and lash part (none for lashes without eyeballs).
std::map<std::uint32_t, Painter> Painters(const Mesh& mesh, const EyeTextureParams& params) {
  const auto vertices = VerticesOfParts(mesh);
  const std::map<std::uint32_t, EyeFrame> frames = EyeFrames(mesh, vertices);
  std::map<std::uint32_t, Painter> painters;
  std::vector<EyeFrame> eyeballs;
  for (const auto& [part, frame] : frames) {
    painters[part] = [frame, params](const glm::vec3& p) { return glm::vec4(ColourAt(frame, params, p), 1.0f); };
    if (RoleOfPart(mesh.part_names[part]) == PartRole::kSclera) eyeballs.push_back(frame);
  }
  if (eyeballs.empty()) return painters;
  for (std::uint32_t part = 0; part < mesh.part_names.size(); ++part) {
    if (RoleOfPart(mesh.part_names[part]) == PartRole::kLashes && !vertices[part].empty()) {
      painters[part] = LashPainter(mesh, vertices[part], eyeballs);
    }
  }
  return painters;
}

// A texture being painted: linear RGBA and which texels a triangle covers.
struct Canvas {
  int size = 0;
  cv::Mat colour;   // CV_32FC4
  cv::Mat covered;  // CV_8U
};

// Each texel centre under the triangle's UVs (OBJ's convention: v up, the
// tile the triangle lies in) takes the colour of its surface point.
void PaintTriangle(Canvas& canvas, const Mesh& mesh, std::size_t t, const Painter& paint) {
  glm::dvec2 uv[3];
  glm::vec2 centre(0.0f);
  for (int k = 0; k < 3; ++k) centre += mesh.corner_uvs[3 * t + static_cast<std::size_t>(k)] / 3.0f;
  const glm::vec2 tile = glm::floor(centre);
  for (int k = 0; k < 3; ++k) {
    const glm::vec2 local = mesh.corner_uvs[3 * t + static_cast<std::size_t>(k)] - tile;
    uv[k] = glm::dvec2(local.x, 1.0f - local.y) * static_cast<double>(canvas.size) - 0.5;
  }
  const Triangle& tri = mesh.triangles[t];
  ForEachTexelIn(uv, canvas.size, [&](int x, int y, double w0, double w1, double w2) {
    const glm::vec3 p = glm::vec3(w0 * glm::dvec3(mesh.positions[tri[0]]) + w1 * glm::dvec3(mesh.positions[tri[1]]) +
                                  w2 * glm::dvec3(mesh.positions[tri[2]]));
    const glm::vec4 c = paint(p);
    canvas.colour.at<cv::Vec4f>(y, x) = cv::Vec4f(c.r, c.g, c.b, c.a);
    canvas.covered.at<std::uint8_t>(y, x) = 1;
  });
}

// Texels next to painted ones take their colour, a few rings out, so that
// filtering across a UV seam does not bring in the background.
void GrowPainted(Canvas& canvas, int rings) {
  for (int ring = 0; ring < rings; ++ring) {
    const cv::Mat covered = canvas.covered.clone();
    for (int y = 0; y < canvas.size; ++y) {
      for (int x = 0; x < canvas.size; ++x) {
        if (covered.at<std::uint8_t>(y, x)) continue;
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= canvas.size || ny >= canvas.size || !covered.at<std::uint8_t>(ny, nx)) continue;
          canvas.colour.at<cv::Vec4f>(y, x) = canvas.colour.at<cv::Vec4f>(ny, nx);
          canvas.covered.at<std::uint8_t>(y, x) = 1;
          break;
        }
      }
    }
  }
}

// sRGB colour (and linear alpha, when `with_alpha`) as an 8-bit PNG.
EncodedImage EncodeCanvas(const Canvas& canvas, const std::string& name, bool with_alpha) {
  const int channels = with_alpha ? 4 : 3;
  std::vector<std::uint8_t> texels(static_cast<std::size_t>(canvas.size) * canvas.size * channels);
  std::uint8_t* texel = texels.data();
  for (int y = 0; y < canvas.size; ++y) {
    for (int x = 0; x < canvas.size; ++x, texel += channels) {
      const cv::Vec4f c = canvas.colour.at<cv::Vec4f>(y, x);
      for (int k = 0; k < 3; ++k) texel[k] = ToByte(LinearToSrgb(std::clamp(c[k], 0.0f, 1.0f)));
      if (with_alpha) texel[3] = ToByte(c[3]);
    }
  }
  return EncodePng(texels, canvas.size, canvas.size, channels, name);
}

// A file name for the material's image, unused by the mesh's other images.
std::string ImageName(const Mesh& mesh, const std::string& material_name) {
  std::string stem;
  for (char c : material_name) stem += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  if (stem.empty()) stem = "eye";
  const auto used = [&](const std::string& name) {
    return std::any_of(mesh.images.begin(), mesh.images.end(), [&](const EncodedImage& i) { return i.name == name; });
  };
  std::string name = stem + "_painted.png";
  for (int n = 2; used(name); ++n) name = stem + "_painted_" + std::to_string(n) + ".png";
  return name;
}

// The materials only painted parts use, none with an image yet, each with its triangles.
std::map<std::uint32_t, std::vector<std::size_t>> PaintableMaterials(const Mesh& mesh,
                                                                     const std::map<std::uint32_t, Painter>& painters) {
  std::map<std::uint32_t, std::vector<std::size_t>> triangles;
  std::vector<bool> elsewhere(mesh.materials.size(), false);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const std::uint32_t m = mesh.triangle_materials[t];
    if (painters.count(mesh.triangle_parts[t]) != 0 && mesh.materials[m].base_colour_image < 0) {
      triangles[m].push_back(t);
    } else {
      elsewhere[m] = true;
    }
  }
  std::erase_if(triangles, [&](const auto& entry) { return elsewhere[entry.first]; });
  return triangles;
}

// What texels no triangle covers show: the part's plain colour (lashes: none).
glm::vec4 Background(PartRole role) {
  switch (role) {
    case PartRole::kSclera: return {kSclera, 1.0f};
    case PartRole::kLashes: return {kLash, 0.0f};
    default: return {kIrisOuter, 1.0f};
  }
}

}  // namespace

std::size_t PaintEyeTextures(Mesh& mesh, const EyeTextureParams& params) {
  std::string problem;
  if (!mesh.Validate(&problem)) throw InvalidInputError("eye textures: " + problem, "mesh");
  if (params.size < 1 || params.size > 4096) throw InvalidInputError("eye textures: size out of range", "size");
  if (mesh.corner_uvs.empty() || mesh.triangle_parts.empty() || mesh.triangle_materials.empty()) return 0;
  const std::map<std::uint32_t, Painter> painters = Painters(mesh, params);
  std::size_t painted = 0;
  for (const auto& [material, triangles] : PaintableMaterials(mesh, painters)) {
    const PartRole role = RoleOfPart(mesh.part_names[mesh.triangle_parts[triangles.front()]]);
    const glm::vec4 background = Background(role);
    const int size = role == PartRole::kLashes ? 2 * params.size : params.size;  // hairs want texels
    Canvas canvas{.size = size,
                  .colour = cv::Mat(size, size, CV_32FC4, cv::Scalar(background.r, background.g, background.b, background.a)),
                  .covered = cv::Mat(size, size, CV_8U, cv::Scalar(0))};
    for (std::size_t t : triangles) PaintTriangle(canvas, mesh, t, painters.at(mesh.triangle_parts[t]));
    GrowPainted(canvas, 4);
    Material& m = mesh.materials[material];
    const bool with_alpha = role == PartRole::kLashes;
    mesh.images.push_back(EncodeCanvas(canvas, ImageName(mesh, m.name), with_alpha));
    m.base_colour = glm::vec4(1.0f, 1.0f, 1.0f, with_alpha ? 1.0f : m.base_colour.a);
    m.base_colour_image = static_cast<std::int32_t>(mesh.images.size() - 1);
    ++painted;
  }
  return painted;
}

}  // namespace facerig
