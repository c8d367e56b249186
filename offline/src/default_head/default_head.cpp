// Assembly of the default head: control face -> 2 linear + 2 Loop
// subdivisions -> projection onto the sculpt -> parts -> shapes -> Rig.
#include "facerig/offline/default_head/default_head.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "default_head/internal.h"
#include "facerig/runtime/rig_builder.h"
#include "geometry/mesh_edges.h"

namespace facerig {
namespace default_head {
namespace {

// Walks the dense boundary from corner `from` to corner `to` both ways and
// returns the way that passes through `through` (corners excluded).
std::vector<std::uint32_t> BoundaryChain(const std::vector<Triangle>& triangles, std::uint32_t from,
                                         std::uint32_t to, std::uint32_t through) {
  std::map<std::uint32_t, std::vector<std::uint32_t>> next;
  for (const BoundarySide& side : BoundarySides(triangles)) {
    next[side.a].push_back(side.b);
    next[side.b].push_back(side.a);
  }
  for (std::uint32_t start : next.at(from)) {
    std::vector<std::uint32_t> chain;
    std::uint32_t previous = from, current = start;
    while (current != to && chain.size() < triangles.size()) {
      chain.push_back(current);
      const std::vector<std::uint32_t>& n = next.at(current);
      if (n.size() != 2) throw std::logic_error("default head: boundary vertex of valence != 2");
      const std::uint32_t following = n[0] == previous ? n[1] : n[0];
      previous = current;
      current = following;
    }
    if (current == to && std::find(chain.begin(), chain.end(), through) != chain.end()) return chain;
  }
  throw std::logic_error("default head: opening chain not found");
}

// The lip margins, projected separately, leave a slit between the lips that
// shows the teeth; at rest each upper margin vertex meets its lower partner
// (kept a hair apart so the opening keeps its orientation).
void CloseLipsAtRest(HeadGeometry& head) {
  constexpr double kHalfGap = 0.002;  // cm
  for (std::size_t i = 0; i < head.upper_lip.size(); ++i) {
    glm::dvec3& upper = head.positions[head.upper_lip[i]];
    glm::dvec3& lower = head.positions[head.lower_lip[i]];
    const glm::dvec3 middle = 0.5 * (upper + lower);
    const glm::dvec3 apart = upper - lower;
    const double length = glm::length(apart);
    const glm::dvec3 up = length > 1e-9 ? apart / length : glm::dvec3(0.0, 1.0, 0.0);
    upper = middle + kHalfGap * up;
    lower = middle - kHalfGap * up;
  }
}

}  // namespace

HeadGeometry BuildSkin() {
  HeadGeometry head;
  head.control = BuildControlMesh();
  const ControlMesh& control = head.control;
  // As in Mattos et al.: two linear steps keep the control shape, two Loop
  // steps smooth it; the corners of the eyes and mouth stay sharp.
  head.subdivision = Subdivide(control.directions.size(), control.triangles, control.corners, 2, 2);
  const std::vector<glm::dvec3> directions = Apply(head.subdivision, control.directions);
  head.positions.reserve(directions.size());
  for (const glm::dvec3& d : directions) head.positions.push_back(SurfacePoint(d));
  head.triangles = head.subdivision.triangles;
  head.skin_count = static_cast<std::uint32_t>(head.positions.size());
  head.parts.push_back({"skin", 0, static_cast<std::uint32_t>(head.triangles.size())});

  for (int side = 0; side < 2; ++side) {
    const ControlMesh::Opening& eye = control.eyes[static_cast<std::size_t>(side)];
    head.upper_lid[static_cast<std::size_t>(side)] =
        BoundaryChain(head.triangles, eye.corner_a, eye.corner_b, eye.upper.front());
    head.lower_lid[static_cast<std::size_t>(side)] =
        BoundaryChain(head.triangles, eye.corner_a, eye.corner_b, eye.lower.front());
  }
  head.upper_lip = BoundaryChain(head.triangles, control.mouth.corner_a, control.mouth.corner_b,
                                 control.mouth.upper.front());
  head.lower_lip = BoundaryChain(head.triangles, control.mouth.corner_a, control.mouth.corner_b,
                                 control.mouth.lower.front());
  if (head.upper_lip.size() != head.lower_lip.size() ||
      head.upper_lid[0].size() != head.lower_lid[0].size()) {
    throw std::logic_error("default head: upper and lower margins differ in length");
  }
  CloseLipsAtRest(head);

  // Jaw weights authored on the control face, subdivided like positions.
  // A trailing '_' names both sides.
  std::vector<double> jaw(control.names.size(), 0.0);
  const std::vector<std::pair<std::string, double>> jaw_control = {
      {"lip_lower_inner", 1.0},  {"lip_lower_outer", 1.0},  {"chin", 1.0},       {"menton", 1.0},
      {"lip_lower_inner_", 1.0}, {"lip_lower_outer_", 1.0},
      {"jaw_", 1.0},             {"jaw_angle_", 0.75}, {"mouth_corner_", 0.5},
      {"cheek_low_", 0.35}};
  for (const auto& [name, weight] : jaw_control) {
    if (name.back() == '_') {
      jaw[control.Find(name + "L")] = weight;
      jaw[control.Find(name + "R")] = weight;
    } else {
      jaw[control.Find(name)] = weight;
    }
  }
  head.jaw_weight = Apply(head.subdivision, jaw);
  // The skull above the hinge never follows the jaw, however far the
  // subdivided weights spread.
  const double hinge_y = Anatomy::JawPivot().y;
  for (std::size_t v = 0; v < head.jaw_weight.size(); ++v) {
    head.jaw_weight[v] *= std::clamp((hinge_y - head.positions[v].y) / 2.5, 0.0, 1.0);
  }
  return head;
}

}  // namespace default_head

Rig BuildDefaultHead(DefaultHeadFeatures* features) {
  default_head::HeadGeometry head = default_head::BuildSkin();
  default_head::AddParts(head);

  RawRig raw;
  raw.units = Units::kCentimetres;
  raw.up_axis = UpAxis::kY;
  raw.positions.reserve(head.positions.size());
  for (const glm::dvec3& p : head.positions) raw.positions.push_back(glm::vec3(p));
  raw.triangles = head.triangles;
  raw.parts = head.parts;
  default_head::DressHead(raw, head);
  raw.shapes = default_head::BuildExpressions(head);
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) throw std::logic_error("default head: invalid rig: " + problem);

  if (features) {
    const default_head::ControlMesh& control = head.control;
    for (int side = 0; side < 2; ++side) {
      const auto s = static_cast<std::size_t>(side);
      features->eye_centres[s] = glm::vec3(default_head::Anatomy::EyeCentre(side));
      features->upper_lid[s] = head.upper_lid[s];
      features->lower_lid[s] = head.lower_lid[s];
    }
    features->eyeball_radius = static_cast<float>(default_head::Anatomy::kEyeRadius);
    features->nose_tip = control.Find("nose_tip");
    features->mouth_corners = {control.Find("mouth_corner_L"), control.Find("mouth_corner_R")};
    features->upper_lip_border = control.Find("lip_upper_outer");
    features->lower_lip_border = control.Find("lip_lower_outer");
    features->cheeks = {control.Find("cheek_inner_L"), control.Find("cheek_inner_R")};
    features->upper_lip = head.upper_lip;
    features->lower_lip = head.lower_lip;
    features->skin_vertex_count = head.skin_count;
    features->control_vertex_count = static_cast<std::uint32_t>(control.names.size());
    features->control_triangle_count = static_cast<std::uint32_t>(control.triangles.size());
  }
  return std::move(*rig);
}

}  // namespace facerig
