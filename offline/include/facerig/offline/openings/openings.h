// Openings of a face mesh: the eyes between their lids and the mouth between
// its lips. One vocabulary for every stage that needs them:
//  - an opening's rims: the target's boundary loops where the opening is a
//    hole in its mesh (BoundaryLoops, OpeningRim);
//  - its margins: the template vertices that meet the vertex across the
//    opening when an expression closes it (OpeningMargin, from the contacts
//    of ContactFinder, openings_contacts.h);
//  - the contacts themselves (OpeningContact), which deformation transfer
//    keeps so that a transferred blink closes;
//  - how closed an opening is in a pose (OpeningMargins, OpeningGap).
// Registration moves the fitted template's margins onto the target's rims
// (AlignMarginsToOpenings), transfer keeps the contacts, topology mapping
// snaps, smooths and closes the target's rims (topology_mapping.h); all take
// their thresholds from one OpeningParams.
//
// Why margins need care (README, "Measurements behind the defaults"):
// registration fits surfaces, not rims, and per-triangle gradients only say
// how each lid bends, not where the other lid is, so without them a
// transferred blink stops short of closing on a target shaped unlike the
// template.
#pragma once

#include <bitset>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

enum class OpeningKind : std::uint8_t { kEye = 0, kMouth };

// The thresholds of every openings step. Distances are fractions of the size
// named in each comment (dimensionless), cosines are in [-1, 1].
struct OpeningParams {
  // --- Contacts: which pairs an expression brings together across an
  // opening (ContactFinder). A contact is a vertex u that the expression
  // moves by more than contact_moving_fraction of its largest motion, and the
  // vertex v of the same part it comes nearest, within contact_reach of u's
  // motion, such that at rest v lies ahead of u (contact_nearest_ahead to
  // contact_farthest_ahead times u's motion away, within acos
  // contact_ahead_cosine of its direction) and across an opening (the
  // straight line between them meets no other triangle of their part, while
  // the shortest path along mesh edges is more than contact_opening_detour
  // times as long).
  float contact_moving_fraction = 0.3f;
  float contact_reach = 0.1f;
  float contact_nearest_ahead = 0.5f;
  float contact_farthest_ahead = 1.5f;
  // About 45 degrees.
  float contact_ahead_cosine = 0.7f;
  // 2 left out the lid corners, where upper and lower lid are joined (ICT's
  // blink: 14 contacts per eye, 17 at 1.75; the worst eye of 8 random faces
  // then closed to 0.0075 of its width instead of 0.017); 1.25 let in
  // mouthClose's lips, which it pushes through each other.
  float contact_opening_detour = 1.75f;

  // --- Margin alignment: the fitted template's margins onto the target's
  // rims (AlignMarginsToOpenings). A margin vertex takes the nearest rim point
  // within margin_max_distance of its opening (its distance to its partner in
  // the fit) ...
  float margin_max_distance = 0.5f;
  // ... on a rim edge whose opening lies the same way: cos of the angle
  // between the margin's direction to its partner and the rim edge's
  // direction away from its triangle, at least this.
  float margin_min_facing = 0.5f;
  // Only where the partner finds a rim point too, and the two rim points lie
  // across an opening margin_min_opening_ratio to 1 / margin_min_opening_ratio
  // times the fit's, in the same direction (cos >= margin_min_facing): the
  // stylized head's lips are a slit 0.5 mm wide, not the opening ICT's lips
  // roll across.
  float margin_min_opening_ratio = 0.5f;
  // Matches whose correction exceeds this many times the median correction
  // are dropped (a corner taking a rim point of the other lid).
  float margin_max_correction_over_median = 3.0f;
  // The correction fades to zero at this many median openings, measured
  // along the template's edges.
  float margin_reach = 1.0f;

  // --- Rims in topology mapping (ComputeTopologyMapping, CloseRims).
  // Distances are fractions of the fitted template's bounding-box diagonal.
  // Vertices on the target's boundary (the rims of mouth and eye openings)
  // look for their template point this far (0.003 is 1.4 mm on ICT-FaceKit)
  // inside their own lip or lid.
  float boundary_inset = 0.003f;
  // Target boundary vertices within this distance of a rim edge of the
  // template (both ends margins, MarginDirection) that opens the same way
  // (cos >= rim_min_facing) take their point on that edge instead, with no
  // inset: the upper rim of an eye or a mouth moves as the template's upper
  // margin. rim_min_facing also decides which neighbours along a target rim
  // lie on the same side.
  float rim_snap_distance = 0.002f;
  float rim_min_facing = 0.5f;
  // Along a target boundary loop with snapped vertices, the mapped values are
  // smoothed over about this distance (a Gaussian's sigma, by passes of
  // (previous + 2 self + next) / 4, neighbours facing the same way only, so an
  // eye's corners stay apart). Why: where the template's margin ends before
  // the target's rim does, the rim vertices past it take an inset point,
  // which moves less, and a closed lid's edge steps between neighbours. A
  // coarse rim (vertices further apart than the radius) is left as it is.
  // 0: off.
  float rim_smoothing_radius = 0.002f;
  // Where an expression brings a rim's two sides to within this fraction of
  // their rest distance (the fitted template's lids meeting on a blink), the
  // target's rim closes: each side moves half the remaining gap towards the
  // other (or back, where they cross; fully from half this fraction down),
  // and the lid around follows, fading to nothing rim_closing_reach times the
  // rest distance away. Why: the template's lid, fitted to a surface, is
  // shaped unlike the target's, so its closed rim can leave a slit that shows
  // the eye, or cross the lower rim. 0: off.
  float rim_closing_ratio = 0.3f;
  float rim_closing_reach = 0.5f;
};

// A vertex on the margin of an opening, and the vertex across the opening
// that it meets in one of the template's expressions.
struct OpeningMargin {
  std::uint32_t vertex;
  std::uint32_t partner;
};

// A fitted template margin vertex and the unit direction from it across the
// opening (towards its partner in the fit), in the target's frame.
struct MarginDirection {
  std::uint32_t vertex;
  glm::vec3 into_opening;
};

// One contact of an expression: the moving vertex meets its partner.
struct OpeningContact {
  std::uint32_t moving;
  std::uint32_t partner;
  glm::vec3 offset;  // moving - partner in the template's expression
};

// A rim vertex with its neighbours along the rim (indices into
// OpeningRim::vertices; itself where a neighbour faces another way).
struct RimNeighbours {
  std::uint32_t vertex;    // target vertex
  std::uint32_t previous;  // index into OpeningRim::vertices
  std::uint32_t next;
};

// A target vertex that follows a rim's closing.
struct RimBand {
  std::uint32_t vertex;
  std::uint32_t rim_index;  // into OpeningRim::vertices: the rim vertex it follows
  float weight;
};

// A target's rim (a boundary loop with snapped vertices, its eye or mouth
// opening found by the template's margins): its vertices along the loop and
// the number of smoothing passes for its vertex spacing
// (OpeningParams::rim_smoothing_radius); per vertex, the direction into the
// opening and the rest distance to the opposite side (0: none); and the
// target vertices that follow a closing (OpeningParams::rim_closing_ratio).
struct OpeningRim {
  std::vector<RimNeighbours> vertices;
  std::vector<glm::vec3> into_opening;
  std::vector<float> rest_gap;
  std::vector<RimBand> band;
  int passes = 0;
};

// --- Rims and eye landmarks (openings_eyes.cpp) ---

// Boundary loops of the mesh (holes: eye openings, an open mouth, the neck),
// as vertex chains of at least 6 vertices. Non-manifold corners end a chain early.
std::vector<std::vector<std::uint32_t>> BoundaryLoops(std::span<const glm::vec3> positions,
                                                     std::span<const Triangle> triangles);

// Where an eye is a hole in the face mesh (a separate eyeball behind it: most
// game and scanned heads), the hole's boundary is the lid margins, a better
// guide than a 2D detector trained on photographs, which misplaces a stylized
// head's eyes.
//
// Where an eye is an opening in the mesh, its corners (dlib 36/39, 42/45) are
// the ends of the opening's first principal axis. Moves only corners within
// 0.3 eye widths. Returns how many moved.
int CorrectEyeCorners(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                      std::vector<glm::vec3>& points);

// Which of the 68 landmarks (bit k: dlib point k).
using LandmarkMask = std::bitset<68>;

struct EyeOpeningFit {
  int eyes = 0;  // eyes fitted to an opening
  LandmarkMask moved;  // points put on a margin
};

// Each eye (dlib 36-41, 42-47) onto the opening near them: the corners go to
// the ends of its principal axis; a lid point goes onto its upper or lower
// chain, at its place along that axis, when the detector missed the eye (its
// lid points far from the margins) or when `inside` marks it (it landed on
// the eyeball or tear film seen through the opening). Other lid points stay:
// a template's lid landmarks need not lie on its margin. An eye is fitted to
// the largest opening whose centre lies within 0.75 of the detected eye width
// of the detected eye's centre and whose size is 0.2 to 0.8 of that width
// (an iris may be a hole too), unless a point would move farther than 0.75
// of the width (the opening is then not this eye). points: the 68 landmarks.
EyeOpeningFit FitEyesToOpenings(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                std::vector<glm::vec3>& points, const LandmarkMask& inside = {});

// --- Margins and their alignment onto the target's rims (openings_margins.cpp) ---

// Both ends of every contact of every expression (ContactFinder), each vertex
// once (with its first partner), by increasing vertex. ICT-FaceKit: its
// eyelids (the blinks), and a few lip vertices of mouthRoll and jaw shapes
// that the alignment leaves (their partners meet no rim across a like
// opening). Its lips touch at rest: not an opening here.
std::vector<OpeningMargin> FindOpeningMargins(const Rig& template_rig, const OpeningParams& params = {});

struct MarginAlignmentResult {
  std::vector<std::uint32_t> aligned;  // margin vertices moved onto a rim (sorted)
  std::size_t aligned_vertices = 0;  // their count
  std::size_t moved_vertices = 0;    // all vertices the correction moved
  double mean_correction = 0.0;      // over the aligned margin vertices, target units
  double max_correction = 0.0;
};

// The fitted template's margins onto the target's rims where the target's
// opening is a hole in its mesh (its rim is then exact): each margin vertex
// goes onto the nearest rim edge that faces the same way, and the vertices
// around follow smoothly (a harmonic field over the template's edges that
// fades to nothing one opening away). Deformation transfer then closes the
// fitted template's corrected opening, and the target's rim vertices map onto
// its margins. fitted: the template registered onto the target (template
// topology, target frame), corrected in place; template_triangles: the
// template's. Targets without holes near the margins are left as they are.
MarginAlignmentResult AlignMarginsToOpenings(std::span<glm::vec3> fitted, std::span<const Triangle> template_triangles,
                                             std::span<const OpeningMargin> margins,
                                             std::span<const glm::vec3> target_positions,
                                             std::span<const Triangle> target_triangles,
                                             const OpeningParams& params = {});

// The margins that the mapping snaps the target's rims to: those in `aligned`
// (sorted), with the direction towards their partner in `fitted`.
std::vector<MarginDirection> MarginDirections(std::span<const OpeningMargin> margins,
                                              std::span<const std::uint32_t> aligned,
                                              std::span<const glm::vec3> fitted);

// --- Measuring how closed an opening is (openings_gaps.cpp; tests and the bench) ---

// The margins of one opening, found from the template's closing expression:
// upper[i] meets lower[i]. Eyes: lower_margin is the lower lid's margin as a
// polyline (the lid slides as it closes, so the partners mark where the lower
// margin is, not what each upper vertex meets); mouths: empty. width: the
// opening's x extent in the neutral (eye: of the upper lid's moving vertices;
// mouth: of the paired vertices).
struct OpeningMargins {
  OpeningKind kind = OpeningKind::kEye;
  std::vector<std::uint32_t> upper;
  std::vector<std::uint32_t> lower;
  std::vector<std::uint32_t> lower_margin;
  double width = 0.0;
};

// The eyelid margins of one eye, found from the template's blink. upper: the
// upper-lid vertices (moving more than half the blink's largest motion) that
// meet a lower-lid vertex (apart in the neutral, within 10% of the upper
// vertex's motion in the blink); lower: those partners; lower_margin: the
// shortest mesh-edge path (neutral lengths, avoiding the upper lid) from the
// partner of smallest x to that of largest x. Vertices searched:
// [region_first, region_last) (ICT: 0-17038, face and eye sockets, where the
// lid margins are).
// \throw MeshInputError when the blink closes nothing or no mesh path
// joins the lower partners.
OpeningMargins FindEyelidMargins(const Mesh& neutral_mesh, std::span<const glm::vec3> blink,
                                 std::size_t region_first, std::size_t region_last);

// The lip margins, found from the template's closed mouth: ICT's mouthClose is
// made to be added to jawOpen (alone it pushes the lips through each other), so
// open = neutral + jawOpen, closed = neutral + jawOpen + mouthClose. Pairs of a
// vertex that mouthClose moves (more than 0.3 of its largest motion in the
// region) and the vertex it meets: apart in the open pose (by more than 0.3 of
// that motion), within 10% of their open distance in the closed pose. Each
// pair once, upper = the higher of the two in the open pose. Vertices searched:
// [region_first, region_last) (ICT: the face, 0-9408).
// \throw MeshInputError on a vertex count mismatch or when the lips meet nowhere.
OpeningMargins FindLipMargins(std::span<const glm::vec3> neutral, std::span<const glm::vec3> open,
                              std::span<const glm::vec3> closed, std::size_t region_first,
                              std::size_t region_last);

// How closed an opening is on a (transferred) mesh, over its width.
// Eyes: for the upper margin vertices whose x lies within the lower margin's
// x extent in that pose (the lid corners, where the lower polyline ends, are
// left out), the distance to the lower margin polyline, and crossing below it
// (along y). Mouths: the distance of each pair, and lower above upper (y).
struct OpeningGap {
  double mean_gap = 0.0;      // mean distance
  double max_gap = 0.0;       // largest such distance
  double max_crossing = 0.0;  // deepest crossing, >= 0
  std::size_t measured_vertices = 0;  // upper margin vertices (eyes) or pairs (mouths) measured
};
OpeningGap MeasureOpeningGap(std::span<const glm::vec3> positions, const OpeningMargins& margins);

}  // namespace facerig
