// The default head's blend shapes (ARKit names, _L/_R as ICT-FaceKit).
//
// Most shapes are authored as displacements of named control vertices and
// reach the dense mesh through the subdivision matrix (delta = S * delta_c,
// as Mattos et al. carry expressions through its subdivision); the mouth's
// deltas and the jaw's weights are then smoothed over the skin, or they would
// crease it along the control edges (default_head_smoothing.cpp). Motions that are
// rotations are evaluated per dense vertex: the jaw about its hinge with
// control-authored weights (through S), the lids slid over the eyeball in
// eye-centred spherical coordinates (so they never cut through it, and close
// exactly on the dense margin partners), the eyeballs about their centres.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "default_head/internal.h"

namespace facerig::default_head {
namespace {

using Deltas = std::vector<glm::dvec3>;
constexpr double kDropThreshold = 1e-4;  // cm: 1 micrometre
constexpr double kUpperShare = 0.72;     // the upper lid travels most of a blink
// Umbrella iterations of SkinSmoother for the lower face's deltas and the jaw's
// weights: their control-edge kinks round over about a centimetre, and a
// shape still stays on its own side of the face.
constexpr int kFieldSmoothing = 100;

const char* Suffix(int side) { return side == 0 ? "_L" : "_R"; }

// Rotation of p about the axis through `pivot` along the unit x or y axis.
glm::dvec3 RotateX(const glm::dvec3& p, const glm::dvec3& pivot, double angle) {
  const glm::dvec3 q = p - pivot;
  const double c = std::cos(angle), s = std::sin(angle);
  return pivot + glm::dvec3(q.x, c * q.y - s * q.z, s * q.y + c * q.z);
}
glm::dvec3 RotateY(const glm::dvec3& p, const glm::dvec3& pivot, double angle) {
  const glm::dvec3 q = p - pivot;
  const double c = std::cos(angle), s = std::sin(angle);
  return pivot + glm::dvec3(c * q.x + s * q.z, q.y, -s * q.x + c * q.z);
}

// Displacements of control vertices, authored for the left side; the right
// side is the mirror image (x negated).
class ControlDeltas {
 public:
  explicit ControlDeltas(const ControlMesh& control) : control_(control), deltas_(control.names.size()) {}
  // A midline vertex, or a sided vertex given with its full name.
  ControlDeltas& At(const std::string& name, glm::dvec3 d) {
    deltas_[control_.Find(name)] += d;
    return *this;
  }
  // `base` + _L/_R for `side`; d is given for the left side and mirrored.
  ControlDeltas& Side(const std::string& base, int side, glm::dvec3 d) {
    if (side == 1) d.x = -d.x;
    return At(base + Suffix(side), d);
  }
  ControlDeltas& Both(const std::string& base, glm::dvec3 d) { return Side(base, 0, d).Side(base, 1, d); }
  const Deltas& deltas() const { return deltas_; }

 private:
  const ControlMesh& control_;
  Deltas deltas_;
};

// A control-space scalar field (weights), subdivided and smoothed over the skin.
std::vector<double> SkinWeights(const HeadGeometry& head, const SkinSmoother& smoother,
                                const std::map<std::string, double>& control_weights) {
  std::vector<double> w(head.control.names.size(), 0.0);
  for (const auto& [name, value] : control_weights) w[head.control.Find(name)] = value;
  std::vector<double> skin = Apply(head.subdivision, w);
  smoother.Smooth(skin, kFieldSmoothing);
  return skin;
}

// Dense deltas for all vertices from control displacements: the skin through
// S, the inner mouth following its lip vertex, the rigid parts unmoved.
Deltas FromControl(const HeadGeometry& head, const ControlDeltas& control) {
  Deltas dense(head.positions.size(), glm::dvec3(0.0));
  const std::vector<glm::dvec3> skin = Apply(head.subdivision, control.deltas());
  std::copy(skin.begin(), skin.end(), dense.begin());
  for (std::uint32_t i = 0; i < head.mouth_inner.count; ++i) {
    dense[head.mouth_inner.first + i] = head.inner_follow[i] * skin[head.inner_source[i]];
  }
  return dense;
}

// The lower face's shapes move the skin between the mouth corner and the nose
// wing, the cheek and the jaw: their subdivided deltas are smoothed there. The
// lip margins stay, so the inner mouth still follows them.
Deltas FromControlSmoothed(const HeadGeometry& head, const SkinSmoother& smoother, const ControlDeltas& control) {
  Deltas dense = FromControl(head, control);
  smoother.Smooth(dense, kFieldSmoothing);
  return dense;
}

// Mouth shapes fade out below the eyes: the coarse control face would
// otherwise carry a cheek displacement along its long edges up to the temple.
Deltas LowerFace(const HeadGeometry& head, Deltas dense) {
  const double top = Anatomy::EyeCentre(0).y - 0.3;
  for (std::uint32_t v = 0; v < head.skin_count; ++v) {
    dense[v] *= std::clamp((top - head.positions[v].y) / 1.5, 0.0, 1.0);
  }
  return dense;
}

Deltas Zero(const HeadGeometry& head) { return Deltas(head.positions.size(), glm::dvec3(0.0)); }

// How much each vertex rides on the jaw: the skin's weights smoothed (the lip
// margins keep theirs, which the inner mouth copied); the parts keep their own.
std::vector<double> JawWeights(const HeadGeometry& head, const SkinSmoother& smoother) {
  std::vector<double> weights = head.jaw_weight;
  smoother.Smooth(weights, kFieldSmoothing);
  return weights;
}

Deltas JawOpen(const HeadGeometry& head, const SkinSmoother& smoother) {
  constexpr double kAngle = 0.3;  // radians (about 17 degrees) at weight 1
  const std::vector<double> weights = JawWeights(head, smoother);
  Deltas dense = Zero(head);
  for (std::size_t v = 0; v < head.positions.size(); ++v) {
    const double w = weights[v];
    if (w == 0.0) continue;
    const glm::dvec3& p = head.positions[v];
    dense[v] = RotateX(p, Anatomy::JawPivot(), w * kAngle) - p;
  }
  return dense;
}

// Where the lid margins of one eye meet when closed: along the eyeball from
// each upper margin vertex towards its lower partner, `upper_share` of the way.
std::vector<glm::dvec3> LidMeeting(const HeadGeometry& head, int side, double upper_share) {
  const glm::dvec3 c = Anatomy::EyeCentre(side);
  const auto& upper = head.upper_lid[static_cast<std::size_t>(side)];
  const auto& lower = head.lower_lid[static_cast<std::size_t>(side)];
  std::vector<glm::dvec3> meet;
  for (std::size_t i = 0; i < upper.size(); ++i) {
    const glm::dvec3 u = head.positions[upper[i]] - c, l = head.positions[lower[i]] - c;
    const double ru = glm::length(u), rl = glm::length(l);
    const glm::dvec3 un = u / ru, ln = l / rl;
    const double omega = std::acos(std::clamp(glm::dot(un, ln), -1.0, 1.0));
    glm::dvec3 dir = un;
    if (omega > 1e-9) {
      dir = (std::sin((1.0 - upper_share) * omega) * un + std::sin(upper_share * omega) * ln) / std::sin(omega);
    }
    meet.push_back(c + (ru + upper_share * (rl - ru)) * dir);
  }
  return meet;
}

// Eye-centred spherical coordinates: azimuth about the vertical axis
// (towards +X), elevation, radius.
struct EyeSpherical {
  double azimuth, elevation, radius;
};
EyeSpherical ToEye(const glm::dvec3& p, const glm::dvec3& c) {
  const glm::dvec3 q = p - c;
  return {std::atan2(q.x, q.z), std::atan2(q.y, std::hypot(q.x, q.z)), glm::length(q)};
}
glm::dvec3 FromEye(const EyeSpherical& s, const glm::dvec3& c) {
  const double h = s.radius * std::cos(s.elevation);
  return c + glm::dvec3(h * std::sin(s.azimuth), s.radius * std::sin(s.elevation), h * std::cos(s.azimuth));
}

// Slides one lid over the eyeball: in eye-centred coordinates, the elevations
// between the margin and `reach` radians beyond it (away from the opening) are
// remapped so the margin lands on `target_elevation` (per margin vertex) and
// the far end stays put. Radii are kept, so no lid vertex can enter the
// eyeball, and the remap is monotonic, so the lid cannot fold. Margin
// vertices go exactly to `exact_targets` when given.
void SlideLid(const HeadGeometry& head, int side, bool upper, const std::vector<double>& target_elevation,
              double reach, const std::vector<glm::dvec3>* exact_targets, Deltas& dense) {
  const glm::dvec3 c = Anatomy::EyeCentre(side);
  const auto s = static_cast<std::size_t>(side);
  const std::vector<std::uint32_t>& chain = upper ? head.upper_lid[s] : head.lower_lid[s];
  // Margin samples sorted by azimuth (the chain runs inner to outer corner).
  std::vector<std::pair<double, std::size_t>> by_azimuth;
  for (std::size_t i = 0; i < chain.size(); ++i) by_azimuth.push_back({ToEye(head.positions[chain[i]], c).azimuth, i});
  std::sort(by_azimuth.begin(), by_azimuth.end());
  const double sign = upper ? 1.0 : -1.0;  // away from the opening
  for (std::uint32_t v = 0; v < head.skin_count; ++v) {
    const glm::dvec3& p = head.positions[v];
    EyeSpherical e = ToEye(p, c);
    if (e.radius > 3.0) continue;
    // Margin elevation and target at this azimuth (linear between samples).
    const auto hi = std::lower_bound(by_azimuth.begin(), by_azimuth.end(), std::make_pair(e.azimuth, std::size_t{0}));
    std::size_t i0, i1;
    double t = 0.0, outside = 0.0;
    if (hi == by_azimuth.begin()) {
      i0 = i1 = hi->second;
      outside = by_azimuth.front().first - e.azimuth;
    } else if (hi == by_azimuth.end()) {
      i0 = i1 = by_azimuth.back().second;
      outside = e.azimuth - by_azimuth.back().first;
    } else {
      const auto lo = hi - 1;
      i0 = lo->second;
      i1 = hi->second;
      t = (e.azimuth - lo->first) / std::max(hi->first - lo->first, 1e-12);
    }
    const double margin = (1.0 - t) * ToEye(head.positions[chain[i0]], c).elevation +
                          t * ToEye(head.positions[chain[i1]], c).elevation;
    const double target = (1.0 - t) * target_elevation[i0] + t * target_elevation[i1];
    const double beyond = sign * (e.elevation - margin);  // 0 at the margin, > 0 into the lid
    if (beyond < -1e-9 || beyond > reach) continue;
    const double far_end = margin + sign * reach;
    const double remapped = far_end + (e.elevation - far_end) * (far_end - target) / (far_end - margin);
    // Past the corners and far from the eye the slide fades out.
    const double fade = std::clamp(1.0 - outside / 0.25, 0.0, 1.0) * std::clamp((3.0 - e.radius) / 0.8, 0.0, 1.0);
    e.elevation += fade * (remapped - e.elevation);
    dense[v] += FromEye(e, c) - p;
  }
  if (exact_targets) {
    for (std::size_t i = 0; i < chain.size(); ++i) dense[chain[i]] = (*exact_targets)[i] - head.positions[chain[i]];
  }
}

// Per margin vertex: its elevation moved `fraction` of the way to the meeting
// line (fraction 1: closed), or by a fixed `offset` radians.
std::vector<double> MarginTargets(const HeadGeometry& head, int side, bool upper, double fraction,
                                  double offset) {
  const glm::dvec3 c = Anatomy::EyeCentre(side);
  const auto s = static_cast<std::size_t>(side);
  const std::vector<std::uint32_t>& chain = upper ? head.upper_lid[s] : head.lower_lid[s];
  const std::vector<glm::dvec3> meet = LidMeeting(head, side, kUpperShare);
  std::vector<double> targets;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const double from = ToEye(head.positions[chain[i]], c).elevation;
    targets.push_back(from + fraction * (ToEye(meet[i], c).elevation - from) + offset);
  }
  return targets;
}

constexpr double kUpperReach = 0.9, kLowerReach = 0.7;  // radians of lid beyond the margin

Deltas Blink(const HeadGeometry& head, int side) {
  const std::vector<glm::dvec3> meet = LidMeeting(head, side, kUpperShare);
  Deltas dense = Zero(head);
  SlideLid(head, side, true, MarginTargets(head, side, true, 1.0, 0.0), kUpperReach, &meet, dense);
  SlideLid(head, side, false, MarginTargets(head, side, false, 1.0, 0.0), kLowerReach, &meet, dense);
  return dense;
}

Deltas EyeWide(const HeadGeometry& head, int side) {
  // Lids only (the brows have their own shapes).
  Deltas dense = Zero(head);
  SlideLid(head, side, true, MarginTargets(head, side, true, 0.0, 0.22), kUpperReach, nullptr, dense);
  SlideLid(head, side, false, MarginTargets(head, side, false, 0.0, -0.1), kLowerReach, nullptr, dense);
  return dense;
}

Deltas EyeSquint(const HeadGeometry& head, int side) {
  Deltas dense = FromControl(head, ControlDeltas(head.control)
                                       .Side("cheek_inner", side, {0.0, 0.3, 0.12})
                                       .Side("lid_below", side, {0.0, 0.12, 0.05}));
  SlideLid(head, side, true, MarginTargets(head, side, true, 0.15, 0.0), kUpperReach, nullptr, dense);
  SlideLid(head, side, false, MarginTargets(head, side, false, 0.5, 0.0), kLowerReach, nullptr, dense);
  return dense;
}

// Eyeball rotations: about x (up/down) or y (in/out) through the eye centre.
Deltas EyeLook(const HeadGeometry& head, int side, bool vertical, double angle) {
  Deltas dense = Zero(head);
  const glm::dvec3 c = Anatomy::EyeCentre(side);
  for (std::uint32_t i = 0; i < head.eyeballs.count; ++i) {
    const std::uint32_t v = head.eyeballs.first + i;
    const glm::dvec3& p = head.positions[v];
    if ((p.x > 0.0) != (side == 0)) continue;
    dense[v] = (vertical ? RotateX(p, c, angle) : RotateY(p, c, angle)) - p;
  }
  return dense;
}

// The expressions in the order they are emitted.
struct ShapeList {
  const HeadGeometry& head;
  const SkinSmoother& smoother;
  std::vector<std::pair<std::string, Deltas>> shapes;

  void Add(std::string name, Deltas deltas) { shapes.emplace_back(std::move(name), std::move(deltas)); }
  // Only the mouth and cheek shapes touch midline vertices (the middle of the
  // lips moves a little with either side), with about half the motion.
  void Sided(int side, const char* name, const ControlDeltas& deltas) {
    // The mouth shapes' deltas are smoothed; a cheek puff's is not, as it
    // would spread across the chin to the other cheek.
    const bool lips = std::string(name).starts_with("mouth");
    const bool mouth = lips || std::string(name).starts_with("cheek");
    Deltas dense = lips ? FromControlSmoothed(head, smoother, deltas) : FromControl(head, deltas);
    Add(std::string(name) + Suffix(side), mouth ? LowerFace(head, std::move(dense)) : std::move(dense));
  }
};

// mouthClose: the lips return to each other while the jaw stays open, so
// it cancels the jaw's motion on the lips (jawOpen w + mouthClose w = lips shut).
Deltas MouthClose(const HeadGeometry& head, const SkinSmoother& smoother, const Deltas& jaw) {
  std::vector<double> mask = SkinWeights(head, smoother,
                                         {{"lip_lower_inner", 1.0}, {"lip_lower_outer", 1.0},
                                          {"lip_lower_inner_L", 1.0}, {"lip_lower_inner_R", 1.0},
                                          {"lip_lower_outer_L", 1.0}, {"lip_lower_outer_R", 1.0},
                                          {"mouth_corner_L", 1.0}, {"mouth_corner_R", 1.0},
                                          {"lip_upper_inner", 1.0}, {"lip_upper_inner_L", 1.0},
                                          {"lip_upper_inner_R", 1.0}, {"chin", 0.15}});
  Deltas close = Zero(head);
  for (std::uint32_t v = 0; v < head.skin_count; ++v) close[v] = -mask[v] * jaw[v];
  for (std::uint32_t i = 0; i < head.mouth_inner.count; ++i) {
    const std::uint32_t v = head.mouth_inner.first + i;
    close[v] = -head.inner_follow[i] * mask[head.inner_source[i]] * jaw[v];
  }
  return close;
}

// Jaw and lips, unsided.
void AddJawAndLipShapes(ShapeList& list) {
  const HeadGeometry& head = list.head;
  const ControlMesh& control = head.control;
  auto add = [&](std::string name, Deltas deltas) { list.Add(std::move(name), std::move(deltas)); };
  const SkinSmoother& smoother = list.smoother;
  const Deltas jaw = JawOpen(head, smoother);
  add("jawOpen", jaw);
  add("mouthClose", MouthClose(head, smoother, jaw));
  // "oh": the lips protrude and the corners come in; the opening itself is
  // mostly the jaw's, so the upper lip rises little and the teeth stay behind the lips.
  Deltas funnel = FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_upper_inner", {0.0, 0.2, 0.6})
      .At("lip_lower_inner", {0.0, -0.38, 0.55})
      .Both("lip_upper_inner", {-0.45, 0.18, 0.55})
      .Both("lip_lower_inner", {-0.45, -0.34, 0.5})
      .Both("mouth_corner", {-1.3, 0.0, 0.3})
      .At("lip_upper_outer", {0.0, 0.05, 0.35})
      .At("lip_lower_outer", {0.0, -0.12, 0.3})
      .Both("lip_upper_outer", {-0.35, 0.06, 0.3})
      .Both("lip_lower_outer", {-0.35, -0.1, 0.28})
      // The cheeks follow the corners in, so the skin between does not fold.
      .Both("cheek_low", {-0.4, 0.0, 0.1})
      .At("chin", {0.0, -0.05, 0.1}));
  RoundMouthOpening(head, funnel);
  add("mouthFunnel", std::move(funnel));
  add("mouthPucker", FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_upper_inner", {0.0, -0.02, 0.6})
      .At("lip_lower_inner", {0.0, 0.02, 0.55})
      .Both("lip_upper_inner", {-0.35, -0.02, 0.55})
      .Both("lip_lower_inner", {-0.35, 0.02, 0.5})
      .Both("mouth_corner", {-0.7, 0.0, 0.35})
      .At("lip_upper_outer", {0.0, -0.05, 0.55})
      .At("lip_lower_outer", {0.0, 0.05, 0.5})
      .Both("lip_upper_outer", {-0.3, -0.05, 0.5})
      .Both("lip_lower_outer", {-0.3, 0.05, 0.45})
      .At("chin", {0.0, 0.0, 0.1})));
  add("mouthRollLower", FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_lower_outer", {0.0, 0.3, -0.45})
      .Both("lip_lower_outer", {0.0, 0.25, -0.4})
      .At("lip_lower_inner", {0.0, 0.0, -0.35})
      .Both("lip_lower_inner", {0.0, 0.0, -0.3})));
  add("mouthRollUpper", FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_upper_outer", {0.0, -0.3, -0.45})
      .Both("lip_upper_outer", {0.0, -0.25, -0.4})
      .At("lip_upper_inner", {0.0, 0.0, -0.35})
      .Both("lip_upper_inner", {0.0, 0.0, -0.3})));
}

// Lips pressed, stretched, smiling, frowning.
void AddSidedLipShapes(ShapeList& list, int side) {
  const ControlMesh& control = list.head.control;
  auto sided = [&](const char* shape, const ControlDeltas& deltas) { list.Sided(side, shape, deltas); };
  sided("mouthPress", ControlDeltas(control)
                          .Side("lip_upper_inner", side, {0.0, 0.0, -0.12})
                          .Side("lip_lower_inner", side, {0.0, 0.0, -0.12})
                          .Side("lip_upper_outer", side, {0.0, -0.15, -0.15})
                          .Side("lip_lower_outer", side, {0.0, 0.17, -0.15})
                          .At("lip_upper_outer", {0.0, -0.07, -0.07})
                          .At("lip_lower_outer", {0.0, 0.08, -0.07})
                          .Side("mouth_corner", side, {0.05, 0.0, -0.05}));
  sided("mouthStretch", ControlDeltas(control)
                            .Side("mouth_corner", side, {0.5, -0.25, -0.2})
                            .Side("lip_lower_inner", side, {0.2, -0.18, -0.05})
                            .Side("lip_lower_outer", side, {0.2, -0.22, -0.05})
                            .Side("lip_upper_inner", side, {0.15, 0.0, -0.03})
                            .Side("lip_upper_outer", side, {0.15, 0.0, -0.03})
                            .Side("cheek_low", side, {0.15, -0.1, 0.0}));
  sided("mouthSmile", ControlDeltas(control)
                          .Side("mouth_corner", side, {0.45, 0.6, -0.3})
                          .Side("lip_upper_inner", side, {0.15, 0.18, -0.05})
                          .Side("lip_lower_inner", side, {0.15, 0.22, -0.05})
                          .Side("lip_upper_outer", side, {0.15, 0.15, -0.05})
                          .Side("lip_lower_outer", side, {0.15, 0.15, -0.05})
                          .Side("cheek_low", side, {0.15, 0.4, 0.15})
                          .Side("cheek_inner", side, {0.0, 0.2, 0.12})
                          .Side("nose_wing", side, {0.03, 0.05, 0.0})
                          .Side("lid_below", side, {0.0, 0.08, 0.02}));
  sided("mouthFrown", ControlDeltas(control)
                          .Side("mouth_corner", side, {0.05, -0.55, -0.05})
                          .Side("lip_lower_outer", side, {0.0, -0.15, 0.0})
                          .Side("lip_lower_inner", side, {0.0, -0.12, 0.0})
                          .Side("lip_upper_inner", side, {0.0, -0.1, 0.0})
                          .Side("cheek_low", side, {0.0, -0.15, 0.0}));
}

// Lips up and down, cheek puff, sneer.
void AddSidedMouthShapes(ShapeList& list, int side) {
  const ControlMesh& control = list.head.control;
  auto sided = [&](const char* shape, const ControlDeltas& deltas) { list.Sided(side, shape, deltas); };
  sided("mouthLowerDown", ControlDeltas(control)
                              .Side("lip_lower_inner", side, {0.0, -0.45, 0.02})
                              .Side("lip_lower_outer", side, {0.0, -0.4, 0.05})
                              .At("lip_lower_inner", {0.0, -0.22, 0.0})
                              .At("lip_lower_outer", {0.0, -0.2, 0.02})
                              .Side("mouth_corner", side, {0.0, -0.08, 0.0})
                              .At("chin", {0.0, -0.05, 0.0}));
  sided("mouthUpperUp", ControlDeltas(control)
                            .Side("lip_upper_inner", side, {0.0, 0.4, 0.05})
                            .Side("lip_upper_outer", side, {0.0, 0.4, 0.05})
                            .At("lip_upper_inner", {0.0, 0.2, 0.02})
                            .At("lip_upper_outer", {0.0, 0.2, 0.02})
                            .Side("nose_wing", side, {0.0, 0.08, 0.0})
                            .Side("mouth_corner", side, {0.0, 0.05, 0.0}));
  sided("cheekPuff", ControlDeltas(control)
                         .Side("cheek_low", side, {0.5, 0.05, 0.3})
                         .Side("cheek_inner", side, {0.1, 0.0, 0.15})
                         .Side("mouth_corner", side, {0.12, 0.0, 0.1})
                         .Side("jaw", side, {0.15, 0.0, 0.1}));
  sided("noseSneer", ControlDeltas(control)
                         .Side("nose_wing", side, {0.05, 0.3, 0.0})
                         .Side("cheek_inner", side, {0.0, 0.2, 0.05})
                         .Side("lip_upper_outer", side, {0.0, 0.12, 0.0})
                         .Side("brow_inner", side, {0.0, -0.15, 0.0}));
}

void AddSidedBrowShapes(ShapeList& list, int side) {
  const ControlMesh& control = list.head.control;
  auto sided = [&](const char* shape, const ControlDeltas& deltas) { list.Sided(side, shape, deltas); };
  sided("browInnerUp", ControlDeltas(control)
                           .Side("brow_inner", side, {0.0, 0.7, 0.05})
                           .Side("brow_mid", side, {0.0, 0.3, 0.0})
                           .Side("lid_fold", side, {0.0, 0.15, 0.0}));
  sided("browDown", ControlDeltas(control)
                        .Side("brow_inner", side, {-0.25, -0.55, 0.1})
                        .Side("brow_mid", side, {0.0, -0.4, 0.05})
                        .Side("brow_outer", side, {0.0, -0.2, 0.0})
                        .Side("lid_fold", side, {0.0, -0.2, 0.05}));
  sided("browOuterUp", ControlDeltas(control)
                           .Side("brow_outer", side, {0.0, 0.65, 0.0})
                           .Side("brow_mid", side, {0.0, 0.3, 0.0})
                           .Side("lid_fold", side, {0.0, 0.12, 0.0}));
}

// Lids and gaze: rotations and lid motions on the dense mesh.
void AddSidedEyeShapes(ShapeList& list, int side) {
  const HeadGeometry& head = list.head;
  const std::string s = Suffix(side);
  auto add = [&](std::string name, Deltas deltas) { list.Add(std::move(name), std::move(deltas)); };
  add("eyeBlink" + s, Blink(head, side));
  add("eyeWide" + s, EyeWide(head, side));
  add("eyeSquint" + s, EyeSquint(head, side));
  // Gaze: 20 degrees up, 25 down, 30 in and out. "In" turns towards the nose.
  const double in = side == 0 ? -1.0 : 1.0;
  add("eyeLookUp" + s, EyeLook(head, side, true, -0.35));
  add("eyeLookDown" + s, EyeLook(head, side, true, 0.44));
  add("eyeLookIn" + s, EyeLook(head, side, false, in * 0.52));
  add("eyeLookOut" + s, EyeLook(head, side, false, -in * 0.52));
}

// The jaw slid by `offset` (cm at weight 1): jawForward, jawLeft, jawRight.
Deltas JawSlide(const HeadGeometry& head, const std::vector<double>& jaw_weights, const glm::dvec3& offset) {
  Deltas dense = Zero(head);
  for (std::size_t v = 0; v < head.positions.size(); ++v) dense[v] = jaw_weights[v] * offset;
  return dense;
}

// The lips and corners shifted sideways together (towards +X for the
// character's left): mouthLeft, mouthRight.
ControlDeltas MouthShift(const ControlMesh& control, double dx) {
  ControlDeltas deltas(control);
  for (const char* lip : {"lip_upper_inner", "lip_lower_inner", "lip_upper_outer", "lip_lower_outer"}) {
    deltas.At(lip, {dx, 0.0, 0.0}).At(std::string(lip) + "_L", {dx, 0.0, 0.0}).At(std::string(lip) + "_R", {dx, 0.0, 0.0});
  }
  deltas.At("mouth_corner_L", {dx, 0.0, 0.0}).At("mouth_corner_R", {dx, 0.0, 0.0});
  deltas.At("cheek_low_L", {0.3 * dx, 0.0, 0.0}).At("cheek_low_R", {0.3 * dx, 0.0, 0.0});
  return deltas;
}

// tongueOut: the tongue stretched forward over the lower teeth, its root in
// place, with the jaw a little open so that it passes the lips.
Deltas TongueOut(const HeadGeometry& head, const Deltas& jaw_open) {
  constexpr double kJawShare = 0.3, kReach = 2.6, kLift = 0.55;  // cm at the tip
  Deltas dense = Zero(head);
  for (std::size_t v = 0; v < head.positions.size(); ++v) dense[v] = kJawShare * jaw_open[v];
  double back = head.positions[head.tongue.first].z, front = back;
  for (std::uint32_t i = 0; i < head.tongue.count; ++i) {
    back = std::min(back, head.positions[head.tongue.first + i].z);
    front = std::max(front, head.positions[head.tongue.first + i].z);
  }
  for (std::uint32_t i = 0; i < head.tongue.count; ++i) {
    const std::uint32_t v = head.tongue.first + i;
    const double along = (head.positions[v].z - back) / std::max(front - back, 1e-9);  // 0 root, 1 tip
    dense[v] += glm::dvec3(0.0, kLift * along * (1.0 - 0.5 * along), kReach * along * along);
  }
  return dense;
}

// The ARKit shapes beyond the core set: the jaw's slides, the mouth's shift,
// shrugs and the tongue.
void AddJawSlideAndShrugShapes(ShapeList& list) {
  const HeadGeometry& head = list.head;
  const ControlMesh& control = head.control;
  const SkinSmoother& smoother = list.smoother;
  const std::vector<double> jaw_weights = JawWeights(head, smoother);
  // Unlike a rotation a slide moves the jaw's small weights near the ear as
  // much as the chin: it fades out below the eyes as the mouth shapes do.
  list.Add("jawForward", LowerFace(head, JawSlide(head, jaw_weights, {0.0, 0.0, 0.45})));
  list.Add("jawLeft", LowerFace(head, JawSlide(head, jaw_weights, {0.5, 0.0, 0.0})));
  list.Add("jawRight", LowerFace(head, JawSlide(head, jaw_weights, {-0.5, 0.0, 0.0})));
  list.Add("mouthLeft", LowerFace(head, FromControlSmoothed(head, smoother, MouthShift(control, 0.45))));
  list.Add("mouthRight", LowerFace(head, FromControlSmoothed(head, smoother, MouthShift(control, -0.45))));
  // The chin raiser pushes the lower lip up against the upper one and out.
  list.Add("mouthShrugLower", LowerFace(head, FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_lower_outer", {0.0, 0.12, 0.2})
      .Both("lip_lower_outer", {0.0, 0.1, 0.15})
      .At("lip_lower_inner", {0.0, 0.0, 0.12})
      .Both("lip_lower_inner", {0.0, 0.0, 0.1})
      .At("chin", {0.0, 0.3, 0.2}))));
  list.Add("mouthShrugUpper", LowerFace(head, FromControlSmoothed(head, smoother, ControlDeltas(control)
      .At("lip_upper_outer", {0.0, 0.12, 0.15})
      .Both("lip_upper_outer", {0.0, 0.1, 0.12})
      .At("lip_upper_inner", {0.0, 0.0, 0.1})
      .Both("lip_upper_inner", {0.0, 0.0, 0.08}))));
  list.Add("tongueOut", TongueOut(head, JawOpen(head, smoother)));
}

// Dimples (the corner pulled back) and the cheek raised under the eye.
void AddSidedCheekShapes(ShapeList& list, int side) {
  const ControlMesh& control = list.head.control;
  auto sided = [&](const char* shape, const ControlDeltas& deltas) { list.Sided(side, shape, deltas); };
  sided("mouthDimple", ControlDeltas(control)
                           .Side("mouth_corner", side, {0.2, 0.0, -0.3})
                           .Side("lip_upper_inner", side, {0.06, 0.0, -0.08})
                           .Side("lip_lower_inner", side, {0.06, 0.0, -0.08})
                           .Side("cheek_low", side, {0.05, 0.0, -0.08}));
  sided("cheekSquint", ControlDeltas(control)
                           .Side("cheek_inner", side, {0.0, 0.3, 0.1})
                           .Side("cheek_bone", side, {0.0, 0.22, 0.06})
                           .Side("cheek_low", side, {0.0, 0.1, 0.04})
                           .Side("lid_below", side, {0.0, 0.1, 0.04}));
}

}  // namespace

std::vector<RawBlendShape> BuildExpressions(const HeadGeometry& head) {
  const SkinSmoother smoother(head);
  ShapeList list{head, smoother, {}};
  AddJawAndLipShapes(list);
  for (int side = 0; side < 2; ++side) {
    AddSidedLipShapes(list, side);
    AddSidedMouthShapes(list, side);
    AddSidedBrowShapes(list, side);
    AddSidedEyeShapes(list, side);
  }
  AddJawSlideAndShrugShapes(list);
  for (int side = 0; side < 2; ++side) AddSidedCheekShapes(list, side);
  const auto& shapes = list.shapes;
  std::vector<RawBlendShape> result;
  result.reserve(shapes.size());
  for (const auto& [name, deltas] : shapes) {
    std::vector<glm::vec3> dense(deltas.size());
    for (std::size_t v = 0; v < deltas.size(); ++v) dense[v] = glm::vec3(deltas[v]);
    result.push_back(MakeSparseShape(name, dense, {}, static_cast<float>(kDropThreshold)));
  }
  return result;
}

}  // namespace facerig::default_head
