// Openings of a face mesh: the eyes between their lids and the mouth between
// its lips. One vocabulary for every stage that needs them:
//  - an opening's rims: the target's boundary loops where the opening is a
//    hole in its mesh (BoundaryLoops, OpeningRim);
//  - its margins: the template vertices that meet the vertex across the
//    opening when an expression closes it (OpeningMargin, from the contacts
//    of ContactFinder, contacts.h);
//  - the contacts themselves (OpeningContact), which deformation transfer
//    keeps so that a transferred blink closes;
//  - how closed an opening is in a pose (OpeningMargins, OpeningGap).
// Registration moves the fitted template's margins onto the target's rims
// (AlignMarginsToOpenings, margins.h), transfer keeps the contacts, topology
// mapping snaps, smooths and closes the target's rims (topology_mapping.h);
// all take their thresholds from one OpeningParams. eyes.h puts eye landmarks
// on the lid margins; gaps.h measures how closed an opening is.
//
// Why margins need care (docs/benchmarks.md, "Measurements behind the defaults"):
// registration fits surfaces, not rims, and per-triangle gradients only say
// how each lid bends, not where the other lid is, so without them a
// transferred blink stops short of closing on a target shaped unlike the
// template.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

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

}  // namespace facerig
