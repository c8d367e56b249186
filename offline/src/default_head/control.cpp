// The control face: ~70 named feature points (in the spirit of MPEG-4 FDPs)
// on the left half and the midline, triangulated automatically, mirrored.
//
// The points are given as directions from the surface origin (the sculpt is
// star shaped from there), so the triangulation of the closed head is the
// convex hull of those unit directions (a Delaunay triangulation on the
// sphere); the openings (eyes, mouth, neck) are the hull triangles whose
// corners all lie on one opening. Triangulating one half and mirroring it
// keeps the mesh exactly symmetric, so _L and _R shapes mirror each other.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "default_head/internal.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

struct NamedPoint {
  const char* name;
  glm::dvec3 position;  // near the surface: only its direction from the origin matters
};

// A point on the skin over the left eyeball, at azimuth (towards +X) and
// elevation in degrees about the eye centre.
glm::dvec3 OnLid(double azimuth, double elevation) {
  const double a = Radians(azimuth), e = Radians(elevation);
  const double r = Anatomy::kEyeRadius + Anatomy::kLidOffset;
  return Anatomy::EyeCentre(0) + r * glm::dvec3(std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e));
}

// Midline points (x = 0), front to back.
std::vector<NamedPoint> MidlinePoints() {
  return {
      {"neck_front_rim", {0.0, -18.5, 4.0}},
      {"menton", {0.0, -11.2, 7.2}},
      {"chin", {0.0, -9.4, 8.3}},
      {"lip_lower_outer", {0.0, -7.25, 8.6}},
      {"lip_lower_inner", {0.0, -6.3, 8.7}},
      {"lip_upper_inner", {0.0, -6.27, 8.7}},
      {"lip_upper_outer", {0.0, -5.45, 8.9}},
      {"subnasale", {0.0, -4.25, 8.9}},
      {"nose_tip", {0.0, -3.3, 10.7}},
      {"nasion", {0.0, 0.9, 7.9}},
      {"forehead", {0.0, 6.5, 7.3}},
      {"crown", {0.0, 11.9, 0.0}},
      {"occiput", {0.0, 0.0, -10.4}},
      {"neck_back_rim", {0.0, -18.5, -6.9}},
  };
}

// Left-half points (x > 0).
std::vector<NamedPoint> LeftPoints() {
  return {
      // Eye opening (on the lid sphere) and the lids around it.
      {"eye_inner_L", OnLid(-49.0, -4.0)},
      {"eye_outer_L", OnLid(50.0, 3.0)},
      {"lid_upper_inner_L", OnLid(-17.0, 19.0)},
      {"lid_upper_outer_L", OnLid(19.0, 20.0)},
      {"lid_lower_inner_L", OnLid(-17.0, -19.0)},
      {"lid_lower_outer_L", OnLid(19.0, -17.0)},
      {"lid_fold_L", OnLid(2.0, 56.0)},
      {"lid_below_L", OnLid(4.0, -50.0)},
      // Brow.
      {"brow_inner_L", {1.5, 1.9, 8.0}},
      {"brow_mid_L", {3.4, 2.3, 7.6}},
      {"brow_outer_L", {5.2, 1.6, 6.0}},
      // Nose and cheek.
      {"nose_wing_L", {1.25, -3.6, 8.9}},
      {"cheek_inner_L", {2.6, -2.0, 7.7}},
      {"cheek_bone_L", {5.0, -1.6, 5.8}},
      {"cheek_low_L", {4.4, -5.2, 5.4}},
      // Mouth opening and lips.
      {"mouth_corner_L", {2.6, -6.28, 7.4}},
      {"lip_upper_inner_L", {1.35, -6.24, 8.45}},
      {"lip_lower_inner_L", {1.35, -6.3, 8.4}},
      {"lip_upper_outer_L", {1.5, -5.5, 8.6}},
      {"lip_lower_outer_L", {1.35, -7.2, 8.4}},
      // Chin and jaw.
      {"jaw_L", {4.3, -9.2, 4.2}},
      {"jaw_angle_L", {5.9, -7.2, -0.4}},
      // Skull.
      {"temple_L", {6.3, 3.0, 3.5}},
      {"back_L", {6.0, 1.0, -6.5}},
      // Neck: the rim lies on the flat cut at its base (default_head_surface.cpp).
      {"neck_front_rim_L", {4.3, -18.5, 2.4}},
      {"neck_side_rim_L", {5.85, -18.5, -1.3}},
      {"neck_back_rim_L", {4.3, -18.5, -5.3}},
  };
}

// Incremental convex hull of points in general position; faces outward.
std::vector<Triangle> ConvexHull(const std::vector<glm::dvec3>& p) {
  std::vector<Triangle> faces;
  if (p.size() < 4) throw std::logic_error("ConvexHull: too few points");
  auto outward = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::dvec3& inside) {
    const glm::dvec3 n = glm::cross(p[b] - p[a], p[c] - p[a]);
    return glm::dot(n, inside - p[a]) < 0.0 ? Triangle{a, b, c} : Triangle{a, c, b};
  };
  // Start from the first four points (not coplanar for our input).
  const glm::dvec3 centre = 0.25 * (p[0] + p[1] + p[2] + p[3]);
  faces = {outward(0, 1, 2, centre), outward(0, 1, 3, centre), outward(0, 2, 3, centre),
           outward(1, 2, 3, centre)};
  for (std::uint32_t i = 4; i < p.size(); ++i) {
    std::vector<Triangle> kept;
    std::set<std::pair<std::uint32_t, std::uint32_t>> visible_edges;
    for (const Triangle& f : faces) {
      const glm::dvec3 n = glm::cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
      if (glm::dot(n, p[i] - p[f[0]]) > 1e-12) {
        for (int k = 0; k < 3; ++k) visible_edges.insert({f[k], f[(k + 1) % 3]});
      } else {
        kept.push_back(f);
      }
    }
    if (visible_edges.empty()) throw std::logic_error("ConvexHull: a point is not extreme");
    // Horizon: visible edges whose twin is not visible; keep their order.
    for (const auto& e : visible_edges) {
      if (!visible_edges.count({e.second, e.first})) kept.push_back({e.first, e.second, i});
    }
    faces = std::move(kept);
  }
  return faces;
}

}  // namespace

std::uint32_t ControlMesh::Find(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<std::uint32_t>(i);
  }
  throw std::out_of_range("default head: no control vertex '" + name + "'");
}

namespace {

// The left half of the control mesh (midline points first, then the left
// points): their convex hull about the surface origin, minus the cut along
// the midline and the triangles inside the eye, mouth and neck openings.
std::vector<Triangle> HalfMeshTriangles(const glm::dvec3& origin, const std::vector<NamedPoint>& midline,
                                        const std::vector<NamedPoint>& left) {

  // Half mesh: midline points nudged to x > 0 (by distinct tiny amounts, so
  // the hull has no exactly coplanar faces), then the left points.
  std::vector<glm::dvec3> half_directions;
  for (std::size_t i = 0; i < midline.size(); ++i) {
    glm::dvec3 d = glm::normalize(midline[i].position - origin);
    d.x = 1e-5 * (1.0 + 0.13 * static_cast<double>(i));
    half_directions.push_back(glm::normalize(d));
  }
  for (const NamedPoint& point : left) half_directions.push_back(glm::normalize(point.position - origin));
  const auto midline_count = static_cast<std::uint32_t>(midline.size());
  std::map<std::string, std::uint32_t> half_index;
  for (std::uint32_t i = 0; i < midline_count; ++i) half_index[midline[i].name] = i;
  for (std::uint32_t i = 0; i < left.size(); ++i) half_index[left[i].name] = midline_count + i;
  auto h = [&](const char* name) { return half_index.at(name); };

  // Openings of the half mesh, as vertex sets: hull triangles inside them go.
  const std::vector<std::vector<std::uint32_t>> openings = {
      {h("eye_inner_L"), h("lid_upper_inner_L"), h("lid_upper_outer_L"), h("eye_outer_L"),
       h("lid_lower_outer_L"), h("lid_lower_inner_L")},
      {h("lip_upper_inner"), h("lip_upper_inner_L"), h("mouth_corner_L"), h("lip_lower_inner_L"),
       h("lip_lower_inner")},
      {h("neck_front_rim"), h("neck_front_rim_L"), h("neck_side_rim_L"), h("neck_back_rim_L"), h("neck_back_rim")},
  };
  std::vector<Triangle> half;
  for (const Triangle& t : ConvexHull(half_directions)) {
    if (t[0] < midline_count && t[1] < midline_count && t[2] < midline_count) continue;  // the cut
    bool inside_opening = false;
    for (const auto& opening : openings) {
      auto on = [&](std::uint32_t v) { return std::find(opening.begin(), opening.end(), v) != opening.end(); };
      inside_opening = inside_opening || (on(t[0]) && on(t[1]) && on(t[2]));
    }
    if (!inside_opening) half.push_back(t);
  }
  // Deterministic, readable order: sort by smallest index rotation.
  for (Triangle& t : half) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(half.begin(), half.end());
  return half;
}

// Mirror: midline, left, right (the left points mirrored, same order), on the surface.
ControlMesh MirrorHalf(const glm::dvec3& origin, const std::vector<NamedPoint>& midline,
                       const std::vector<NamedPoint>& left, const std::vector<Triangle>& half) {
  const auto midline_count = static_cast<std::uint32_t>(midline.size());
  ControlMesh mesh;
  const auto left_count = static_cast<std::uint32_t>(left.size());
  for (const NamedPoint& point : midline) {
    glm::dvec3 d = glm::normalize(point.position - origin);
    d.x = 0.0;
    mesh.names.push_back(point.name);
    mesh.directions.push_back(glm::normalize(d));
  }
  for (const NamedPoint& point : left) {
    mesh.names.push_back(point.name);
    mesh.directions.push_back(glm::normalize(point.position - origin));
  }
  for (std::uint32_t i = 0; i < left_count; ++i) {
    std::string name = left[i].name;
    name.back() = 'R';
    const glm::dvec3 d = mesh.directions[midline_count + i];
    mesh.names.push_back(name);
    mesh.directions.push_back({-d.x, d.y, d.z});
  }
  auto mirrored = [&](std::uint32_t v) { return v < midline_count ? v : v + left_count; };
  for (const Triangle& t : half) mesh.triangles.push_back(t);
  for (const Triangle& t : half) mesh.triangles.push_back({mirrored(t[0]), mirrored(t[2]), mirrored(t[1])});

  for (const glm::dvec3& d : mesh.directions) mesh.positions.push_back(SurfacePoint(d));
  return mesh;
}

// The eye and mouth openings (corners, upper and lower rims) and the corner flags.
void MarkOpenings(ControlMesh& mesh) {
  mesh.corners.assign(mesh.names.size(), 0);
  for (const char* side : {"_L", "_R"}) {
    const std::string s = side;
    ControlMesh::Opening& eye = mesh.eyes[s == "_L" ? 0 : 1];
    eye.corner_a = mesh.Find("eye_inner" + s);
    eye.corner_b = mesh.Find("eye_outer" + s);
    eye.upper = {mesh.Find("lid_upper_inner" + s), mesh.Find("lid_upper_outer" + s)};
    eye.lower = {mesh.Find("lid_lower_inner" + s), mesh.Find("lid_lower_outer" + s)};
    mesh.corners[eye.corner_a] = mesh.corners[eye.corner_b] = 1;
    mesh.corners[mesh.Find("mouth_corner" + s)] = 1;
  }
  mesh.mouth.corner_a = mesh.Find("mouth_corner_R");
  mesh.mouth.corner_b = mesh.Find("mouth_corner_L");
  mesh.mouth.upper = {mesh.Find("lip_upper_inner_R"), mesh.Find("lip_upper_inner"), mesh.Find("lip_upper_inner_L")};
  mesh.mouth.lower = {mesh.Find("lip_lower_inner_R"), mesh.Find("lip_lower_inner"), mesh.Find("lip_lower_inner_L")};
}

// The openings must be exactly the boundary loops: every boundary edge on
// an opening, every opening edge on the boundary.
void CheckOpeningsAreBoundaries(const ControlMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_use;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++edge_use[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  }
  std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
  auto chain = [&](const ControlMesh::Opening& o) {
    for (const auto* c : {&o.upper, &o.lower}) {
      std::vector<std::uint32_t> path = {o.corner_a};
      path.insert(path.end(), c->begin(), c->end());
      path.push_back(o.corner_b);
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        expected.insert({std::min(path[i], path[i + 1]), std::max(path[i], path[i + 1])});
      }
    }
  };
  chain(mesh.eyes[0]);
  chain(mesh.eyes[1]);
  chain(mesh.mouth);
  const std::vector<std::string> rim = {"neck_front_rim", "neck_front_rim_L", "neck_side_rim_L", "neck_back_rim_L",
                                        "neck_back_rim", "neck_back_rim_R", "neck_side_rim_R", "neck_front_rim_R"};
  for (std::size_t i = 0; i < rim.size(); ++i) {
    const std::uint32_t a = mesh.Find(rim[i]), b = mesh.Find(rim[(i + 1) % rim.size()]);
    expected.insert({std::min(a, b), std::max(a, b)});
  }
  for (const auto& [edge, uses] : edge_use) {
    if (uses > 2 || (uses == 1) != (expected.count(edge) == 1)) {
      throw std::logic_error("default head control mesh: edge " + mesh.names[edge.first] + " - " +
                             mesh.names[edge.second] + " used " + std::to_string(uses) +
                             " times; the openings are not clean");
    }
  }
  for (const auto& edge : expected) {
    if (!edge_use.count(edge)) {
      throw std::logic_error("default head control mesh: opening edge " + mesh.names[edge.first] +
                             " - " + mesh.names[edge.second] + " missing from the triangulation");
    }
  }
}

}  // namespace

ControlMesh BuildControlMesh() {
  const glm::dvec3 origin = SurfaceOrigin();
  const std::vector<NamedPoint> midline = MidlinePoints();
  const std::vector<NamedPoint> left = LeftPoints();
  ControlMesh mesh = MirrorHalf(origin, midline, left, HalfMeshTriangles(origin, midline, left));
  MarkOpenings(mesh);
  CheckOpeningsAreBoundaries(mesh);
  return mesh;
}

}  // namespace facerig::default_head
