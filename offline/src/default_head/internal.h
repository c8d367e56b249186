// Internal pieces of the built-in default head (default_head*.cpp), one topic
// per file: the control face, subdivision, the sculpted surface, the separate
// parts (eyes, teeth, mouth) and the expressions. Units: centimetres, +Y up,
// the face looks along +Z, the character's left is +X (as ICT-FaceKit).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Sparse>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::default_head {

// The low-poly control face: a closed head with holes for the eyes, the
// mouth and the bottom of the neck, its vertices on the sculpted surface.
// Vertices are named (MPEG-4 FDP-like): midline names have no suffix, sided
// ones end in _L (the character's left, +X) or _R.
struct ControlMesh {
  std::vector<std::string> names;
  std::vector<glm::dvec3> directions;  // unit, from SurfaceOrigin()
  std::vector<glm::dvec3> positions;   // on the surface
  std::vector<Triangle> triangles;     // outward facing
  std::vector<std::uint8_t> corners;   // 1: sharp boundary corner (eye and mouth corners)
  // An opening: two corners and the chains between them (corners excluded,
  // ordered from corner_a to corner_b). Eyes: inner to outer corner; mouth:
  // right (-X) to left corner.
  struct Opening {
    std::uint32_t corner_a = 0, corner_b = 0;
    std::vector<std::uint32_t> upper, lower;
  };
  std::array<Opening, 2> eyes;  // [0] left, [1] right
  Opening mouth;

  // Index of a named vertex; throws std::out_of_range when absent.
  std::uint32_t Find(const std::string& name) const;
};

ControlMesh BuildControlMesh();

// Subdivision with per-vertex correspondence: dense = S * control. Control
// vertices keep their indices (the first rows of S); each step appends one
// vertex per edge. Boundaries use the curve rules (linear: midpoints; Loop:
// 1/8 3/4 1/8 and midpoints); corner vertices stay where they are.
struct Subdivision {
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix;  // dense_count x control_count
  std::vector<Triangle> triangles;
};
Subdivision Subdivide(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                      const std::vector<std::uint8_t>& corners, int linear_steps, int loop_steps);

// Rows of S applied to per-control-vertex values.
std::vector<double> Apply(const Subdivision& s, const std::vector<double>& control);
std::vector<glm::dvec3> Apply(const Subdivision& s, const std::vector<glm::dvec3>& control);

// The sculpted head surface: an implicit function (negative inside), star
// shaped from SurfaceOrigin(); SurfacePoint casts a ray from there. The head
// is the bare sculpt and the hair's shell over it: the bare sculpt without
// its ears, grown by HairThickness.
glm::dvec3 SurfaceOrigin();
double HeadField(const glm::dvec3& p);
double BareHeadField(const glm::dvec3& p, bool ears);
glm::dvec3 SurfacePoint(const glm::dvec3& direction);
// How thick the hair's shell is over a point (cm; 0 off the hair), from the
// hairline the painted hair follows too (default_head_hair.cpp).
double HairThickness(const glm::dvec3& p);

// Anatomy shared by the surface, the parts and the expressions (centimetres).
struct Anatomy {
  static constexpr double kEyeRadius = 1.2;
  static constexpr double kLidOffset = 0.18;  // lid skin above the eyeball
  static glm::dvec3 EyeCentre(int side) {     // side 0: left (+X), 1: right
    return {side == 0 ? 3.15 : -3.15, 0.35, 5.8};
  }
  static constexpr double kIrisRadius = 0.58;   // stylized: a little large
  static constexpr double kPupilRadius = 0.24;
  static constexpr double kMouthY = -6.25;
  // Jaw hinge: a horizontal axis through both temporomandibular joints.
  static glm::dvec3 JawPivot() { return {0.0, -1.6, -0.2}; }
};

// The assembled dense head before it becomes a rig: the subdivided skin
// first, then the separate parts, each a contiguous vertex block.
struct HeadGeometry {
  struct Range {
    std::uint32_t first = 0, count = 0;
  };
  ControlMesh control;
  Subdivision subdivision;
  std::vector<glm::dvec3> positions;
  std::vector<Triangle> triangles;
  std::vector<RawPart> parts;
  std::uint32_t skin_count = 0;
  // Dense chains on the openings (see ControlMesh::Opening), skin vertices.
  std::array<std::vector<std::uint32_t>, 2> upper_lid, lower_lid;
  std::vector<std::uint32_t> upper_lip, lower_lip;
  Range eyeballs;  // both eyeballs (white, iris, pupil); the side is the sign of x
  Range teeth_upper, teeth_lower, mouth_inner, tongue;
  // UVs of the teeth vertices (upper row, then lower), image rows downwards.
  std::vector<glm::dvec2> teeth_uvs;
  // UVs of the inner mouth's vertices: u around the lips, v the depth (0 at the lips).
  std::vector<glm::dvec2> mouth_uvs;
  // Each inner-mouth vertex follows one lip-margin skin vertex, with a weight
  // that fades from 1 at the lips to 0 at the back of the mouth.
  std::vector<std::uint32_t> inner_source;
  std::vector<double> inner_follow;
  // Jaw rotation weight per vertex (0: skull, 1: fully on the jaw).
  std::vector<double> jaw_weight;
};

// Skin (control mesh, subdivision, projection) and the dense margin chains.
HeadGeometry BuildSkin();
// Appends eyeballs, teeth, inner mouth and tongue (in the rig's part order).
void AddParts(HeadGeometry& head);
// Helpers of the parts: a vertex off the jaw, a part of the given triangles.
std::uint32_t AddVertex(HeadGeometry& head, const glm::dvec3& p);
void AddPart(HeadGeometry& head, const char* name, const std::vector<Triangle>& triangles);
// Both rows of teeth, placed just behind the lips' crease (default_head_teeth.cpp);
// returns the crease's depth (z), which the tongue is placed from too.
double AddTeeth(HeadGeometry& head);
// The blend shapes, dense over all vertices of the head.
std::vector<RawBlendShape> BuildExpressions(const HeadGeometry& head);
// Smooths control-authored fields over the skin (its first skin_count
// entries), the margins of the openings and the neck rim held fixed
// (default_head_smoothing.cpp): subdivided, such a field keeps a kink along
// every control edge, which an expression would show as a crease.
class SkinSmoother {
 public:
  explicit SkinSmoother(const HeadGeometry& head);
  // `iterations` umbrella steps: the kink rounds over about sqrt(iterations)
  // dense edges.
  void Smooth(std::vector<double>& field, int iterations) const;
  void Smooth(std::vector<glm::dvec3>& field, int iterations) const;

 private:
  template <typename T>
  void SmoothField(std::vector<T>& field, int iterations) const;
  // Each skin vertex's neighbours: neighbours_[neighbour_begin_[v] .. neighbour_begin_[v + 1]).
  std::vector<std::uint32_t> neighbour_begin_;
  std::vector<std::uint32_t> neighbours_;
  std::vector<std::uint8_t> fixed_;  // 1: on a boundary, kept
};
// Moves the lip margins of a shape's dense deltas so that at weight 1 the
// mouth opening is an ellipse (default_head_round_mouth.cpp).
void RoundMouthOpening(const HeadGeometry& head, std::vector<glm::dvec3>& deltas);

// UVs (default_head_uv.cpp). The skin: a seamless disc about the crown (the
// neck opening on its rim), the face upright in the lower half. An eyeball:
// a disc about its gaze axis; EyeUvRadius gives the UV radius of a polar
// angle from that axis.
glm::dvec2 SkinUv(const glm::dvec3& position);
glm::dvec2 EyeUv(const glm::dvec3& position, int side);
double EyeUvRadius(double polar_angle);
// One UV per vertex of the head; untextured parts get (0.5, 0.5).
std::vector<glm::vec2> HeadUvs(const HeadGeometry& head);

// Painted textures (default_head_albedo*.cpp, default_head_materials.cpp),
// square, in pixels.
inline constexpr int kSkinTextureSize = 1024;
inline constexpr int kEyeTextureSize = 512;
inline constexpr int kTeethTextureSize = 512;  // upper row's band on top, the lower's below
inline constexpr int kMouthTextureSize = 64;
EncodedImage PaintSkinAlbedo(const HeadGeometry& head, const std::vector<glm::vec2>& uvs);
EncodedImage PaintEyeAlbedo();
EncodedImage PaintTeethAlbedo();
EncodedImage PaintMouthAlbedo();
// Gives `raw` (the head's rig data, parts in place) its UVs, textures and
// materials: skin, eye, teeth, tongue, mouth interior.
void DressHead(RawRig& raw, const HeadGeometry& head);

}  // namespace facerig::default_head
