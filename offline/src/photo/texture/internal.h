// The steps of BakePhotoTexture (photo_texture.h), shared by its files.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/texture.h"

namespace facerig::photo_texture {

// Rec. 601 luma of an RGB colour in [0, 1].
inline float Luma(const glm::vec3& c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; }

// Per texel of the texture being baked, row-major; colours sRGB in [0, 1].
struct TexelLayers {
  int size = 0;
  std::vector<glm::vec3> direct_colour, mirror_colour;
  std::vector<float> direct_weight, mirror_weight;
  std::vector<std::uint8_t> skin;   // 1: inside a skin triangle's UVs
  std::vector<std::uint8_t> cheek;  // 1: its surface point lies on a cheek
  std::vector<std::uint8_t> side;   // 1: its surface point lies behind the symmetry plane
  // Where hair covers the surface (0 none, 1 full) and the hair's colour there:
  // what the photo does not show of the scalp takes that colour instead of skin.
  std::vector<float> scalp;
  std::vector<glm::vec3> hair_colour;
  std::vector<float> tilt;  // its surface normal's up (+Y) component, in [-1, 1]
  // The photo's fitted light at the direct and the mirror sample (PhotoShade; 0: none).
  std::vector<float> direct_shade, mirror_shade;
};

// Each vertex's mirror partner across the face's symmetry plane (-1: none);
// only vertices of skin triangles are paired.
struct MirrorPartners {
  std::vector<std::int32_t> partner;
  glm::vec3 plane_normal{1.0f, 0.0f, 0.0f};  // the symmetry plane: dot(normal, p) = offset
  float plane_offset = 0.0f;
  std::size_t pairs = 0;
  double mean_error = 0.0;  // |reflected vertex - its partner|, mesh units
};
MirrorPartners FindMirrorPartners(const Mesh& mesh, const std::vector<std::uint8_t>& skin_vertex);

// Balls round the cheeks, below and beside the eyes (none without eye parts).
struct CheekRegion {
  bool found = false;
  std::array<glm::vec3, 2> centres{};
  float radius = 0.0f;
  bool Contains(const glm::vec3& p) const;
};
CheekRegion FindCheeks(const Mesh& mesh);

// The centres of the eye parts' vertices either side of the midline, the
// character's left (+X) first; false without eye parts on both sides.
bool FindEyeCentres(const Mesh& mesh, glm::vec3& left, glm::vec3& right);

// The scalp: the surface above a hairline set from the eyes (their spacing
// the unit, the face looking along +Z): high on the forehead, over the ears,
// down to the nape.
struct ScalpRegion {
  // The hairline's shift from the rule is kept per azimuth bin, bins of
  // kShiftBinDegrees centred from -kShiftReach to +kShiftReach.
  static constexpr int kShiftBins = 14;
  static constexpr float kShiftBinDegrees = 10.0f;
  static constexpr float kShiftReach = 65.0f;

  bool found = false;
  glm::vec3 eyes{0.0f}, across{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f}, forward{0.0f, 0.0f, 1.0f};
  float spacing = 1.0f;
  // Eye spacings the hairline lies above (+) or below (-) the rule, per bin
  // (0: the rule); set where the photo shows it by FitHairlineToPhoto.
  std::array<float, kShiftBins> hairline_shift{};
  bool hairline_from_photo = false;  // some bin placed by the photo
  // The rule's hairline: its height above the eyes (eye spacings) by azimuth.
  static float RuleHairline(float azimuth_degrees);
  // The hairline's height above the eyes at an azimuth: the rule, shifted.
  float Hairline(float azimuth_degrees) const;
  // The centre of a shift bin, degrees.
  static float BinCentre(int bin) { return -kShiftReach + kShiftBinDegrees * static_cast<float>(bin); }
  // A point's height above the eyes, eye spacings.
  float Height(const glm::vec3& p) const;
  // How much hair covers p, in [0, 1], with a soft edge.
  float Coverage(const glm::vec3& p) const;
  // Where the photo's hair may be taken: the scalp, and unless the photo
  // placed the hairline, the forehead above the brows (a fringe); in [0, 1].
  float HairMayShow(const glm::vec3& p) const;
  // Degrees about the head's vertical axis from the front, + towards the character's left.
  float Azimuth(const glm::vec3& p) const;
  // `colour` with a little low-frequency variation over the head, as clumps of hair.
  glm::vec3 Vary(const glm::vec3& colour, const glm::vec3& p) const;
};
ScalpRegion FindScalp(const Mesh& mesh);


// The photo's head pixels (PhotoHair::head) and the scalp they may land on;
// unused when `scalp.found` is false.
struct HairSource {
  const PhotoSkinMask* head = nullptr;
  ScalpRegion scalp;
  glm::vec3 colour{0.0f};
  glm::vec3 skin_colour{-1.0f};  // the photo's skin (PhotoSkinMedian); negative: unknown
  // Just below the hairline (within `reach` eye spacings of it, or above it)
  // a photo colour nearer the hair's than the skin's is hair, whatever the
  // skin mask's soft edge says: the fringe and its shadow.
  bool IsHairAt(const glm::vec3& p, const glm::vec3& photo_colour, float reach = 0.2f) const;
};

// Median colour of the photo pixels the skin mask surely takes; false when
// there are too few (or no mask).
bool PhotoSkinMedian(const RgbImage& photo, const PhotoSkinMask& skin, glm::vec3& colour);

// Moves the scalp's hairline, azimuth by azimuth, to where the photo shows
// the forehead meet the hair (the head mask, not the skin mask, nearer the
// hair's colour than the skin's) on the skin vertices facing the camera;
// where the photo shows no clear boundary the rule stays. Nothing without
// the photo's skin colour. Returns how many azimuth bins the photo placed.
int FitHairlineToPhoto(const Mesh& mesh, const std::vector<std::uint8_t>& skin_vertex, const RasterView& camera,
                        const RgbImage& photo, const PhotoSkinMask& skin, HairSource& hair);

// The UV tile (integer part) triangle t's UVs lie in, by their centre.
glm::ivec2 UvTile(const Mesh& mesh, std::size_t t);

// The UV tiles of the skin triangles, the one with the most triangles first
// ({0, 0} alone when there are none).
std::vector<glm::ivec2> SkinUvTiles(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle);

// The photo's fitted light at a surface normal: its brightness (luma), with
// normals turned further from the camera than the fit saw shaded as at the
// edge of what it saw; 0 without a lighting (or with de-lighting off).
class PhotoShade {
 public:
  // `facing_sign`: -1 for a mesh wound clockwise (its normals point inwards).
  PhotoShade(const PhotoLighting& lighting, const PhotoTextureParams& params, float facing_sign);
  float At(const glm::vec3& world_normal) const;

 private:
  const PhotoLighting& lighting_;
  const PhotoTextureParams& params_;
  float facing_sign_ = 1.0f;
  bool active_ = false;
};

// The shade the photo's light is divided by relative to: the median shade of
// the squarely seen skin texels, so the face keeps the photo's brightness
// overall; 0 when no texel has a shade.
float MedianSeenShade(const TexelLayers& layers);

// Divides each direct and mirror colour by its shade over `reference`,
// clamped to [delight_least, delight_most] and so that no channel clips
// (a clipped channel would turn the hue). Nothing when reference <= 0.
void DivideOutLight(TexelLayers& layers, float reference, const PhotoTextureParams& params);

// Fills the layers' direct and mirror samples from the photo for every texel
// of the `baked` triangles (skin triangles of one UV tile), each photo pixel
// weighted by the mask, and the photo's light there (`lighting`); all skin
// triangles count as skin where they hide others.
void ProjectPhoto(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle,
                  const std::vector<std::uint8_t>& baked, const RasterView& camera,
                  const RgbImage& photo, const PhotoSkinMask& mask, const MirrorPartners& mirror,
                  const CheekRegion& cheeks, const HairSource& hair, const PhotoTextureParams& params,
                  const PhotoLighting& lighting, TexelLayers& layers);

// Where the baked triangles wear a painted texture (the built-in head's),
// its local light and dark (strands, clumps) multiply the scalp's hair colours.
void AddPaintedHairDetail(const Mesh& mesh, const std::vector<std::uint8_t>& baked, TexelLayers& layers);

// Scales each side's mirror colours so that, where a texel is seen both
// directly and in its mirror, the two agree on average: one side of a face
// is often lit more than the other.
void BalanceMirrorLight(TexelLayers& layers);

// Median colour of the squarely seen cheek texels (else of all squarely seen
// skin texels; else RoleMaterial's skin), sRGB in [0, 1].
glm::vec3 EstimateSkinColour(const TexelLayers& layers);

// How the photo's light falls on the skin by the surface's tilt (its
// normal's up component): the seen skin's brightness over the skin colour's,
// per tilt bin (1 where the photo shows too little).
struct SkinShading {
  static constexpr int kBins = 8;
  std::array<float, kBins> gain{1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
  // Linear between the bins' centres, held beyond the outer ones.
  float At(float tilt) const;
};
SkinShading EstimateSkinShading(const TexelLayers& layers, const glm::vec3& skin_colour);

// Every texel's colour: direct over mirror over the push-pull diffusion of
// both, which fades over `fill_radius` texels into `skin_colour` shaded by
// the texel's tilt as the photo shades the skin; on the scalp, the hair
// colour takes what direct and mirror leave.
std::vector<glm::vec3> FillTexels(const TexelLayers& layers, const glm::vec3& skin_colour, const SkinShading& shading,
                                  float fill_radius);

}  // namespace facerig::photo_texture
