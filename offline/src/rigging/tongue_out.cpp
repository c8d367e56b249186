#include "facerig/offline/rigging/tongue_out.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <vector>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/shape_names.h"
#include "geometry/bounding_box.h"

namespace facerig {
namespace {

// A vertex counts as carried by the jaw when jawOpen moves it at least this
// share of the most it moves any vertex of the tongue's part.
constexpr double kCarriedShare = 0.25;
// UV edges this many times longer than the part's median (per unit of length
// in 3D) cross a seam between charts.
constexpr double kSeamStretch = 4.0;

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::vector<glm::vec3> DenseDeltas(const Rig& rig, std::size_t shape) {
  std::vector<glm::vec3> dense(rig.vertex_count(), glm::vec3(0.0f));
  const BlendShapeView view = rig.shape(shape);
  for (std::size_t i = 0; i < view.vertex_indices.size(); ++i) dense[view.vertex_indices[i]] = view.position_deltas[i];
  return dense;
}

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t Find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void Join(std::uint32_t a, std::uint32_t b) { parent[Find(a)] = Find(b); }
};

struct Frame {
  glm::dvec3 forward, up;
};

// The part's vertices the jaw carries, grouped by UV chart (one group when
// the rig has no UVs or the part no seams).
std::vector<std::vector<std::uint32_t>> CarriedCharts(const Rig& rig, const VertexRange& part,
                                                      const std::vector<bool>& carried) {
  const auto in_part = [&](std::uint32_t v) { return v >= part.first && v <= part.last && carried[v]; };
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Triangle& t : rig.triangles()) {
    if (!in_part(t[0]) || !in_part(t[1]) || !in_part(t[2])) continue;
    for (int k = 0; k < 3; ++k) edges.emplace_back(t[k], t[(k + 1) % 3]);
  }
  const auto uvs = rig.uvs();
  std::vector<double> stretch;
  if (!uvs.empty()) {
    for (const auto& [a, b] : edges) {
      const double length = glm::length(rig.positions()[a] - rig.positions()[b]);
      stretch.push_back(length > 0.0 ? glm::length(uvs[a] - uvs[b]) / length : 0.0);
    }
  }
  double median = 0.0;
  if (!stretch.empty()) {
    std::vector<double> sorted = stretch;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    median = sorted[sorted.size() / 2];
  }
  UnionFind charts(rig.vertex_count());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (median > 0.0 && stretch[e] > kSeamStretch * median) continue;
    charts.Join(edges[e].first, edges[e].second);
  }
  std::map<std::uint32_t, std::vector<std::uint32_t>> by_root;
  for (std::uint32_t v = part.first; v <= part.last; ++v) {
    if (in_part(v)) by_root[charts.Find(v)].push_back(v);
  }
  std::vector<std::vector<std::uint32_t>> result;
  for (auto& [root, vertices] : by_root) result.push_back(std::move(vertices));
  return result;
}

double MedianDistanceTo(const std::vector<std::uint32_t>& vertices, const std::vector<std::uint32_t>& others,
                        std::span<const glm::vec3> positions) {
  std::vector<double> distances;
  for (std::uint32_t v : vertices) {
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t o : others) best = std::min(best, double(glm::length(positions[v] - positions[o])));
    distances.push_back(best);
  }
  std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                   distances.end());
  return distances[distances.size() / 2];
}

// The tongue among the charts: not hugging the teeth (the gums' median
// distance to them is ~2 % of their size, the tongue's and the floor's over
// 10 %), and the highest of those (the floor lies under the tongue).
std::vector<std::uint32_t> PickTongueChart(std::vector<std::vector<std::uint32_t>> charts,
                                           const std::vector<std::uint32_t>& teeth, const Rig& rig,
                                           const glm::dvec3& up) {
  const auto positions = rig.positions();
  std::size_t total = 0;
  for (const auto& chart : charts) total += chart.size();
  std::vector<std::uint32_t> best;
  double best_height = -std::numeric_limits<double>::infinity();
  for (auto& chart : charts) {
    if (chart.size() < std::max<std::size_t>(8, total / 20)) continue;  // slivers along a seam
    glm::dvec3 centroid(0.0);
    for (std::uint32_t v : chart) centroid += glm::dvec3(positions[v]);
    centroid /= double(chart.size());
    const double size = BoxAround(positions, chart).diagonal();
    if (!teeth.empty() && MedianDistanceTo(chart, teeth, positions) < 0.05 * size) continue;
    const double height = glm::dot(centroid, up);
    if (height > best_height) {
      best_height = height;
      best = std::move(chart);
    }
  }
  return best;
}

}  // namespace

namespace {

struct TongueGeometry {
  std::string part;
  std::vector<std::uint32_t> vertices;
  std::vector<std::uint32_t> lower_teeth;  // teeth the jaw carries
};

std::optional<TongueGeometry> FindTongue(const Rig& rig, const FaceTemplateInfo& info,
                                         const std::vector<glm::vec3>& jaw, const glm::dvec3& up) {
  const TemplatePart* part = nullptr;
  for (const TemplatePart& candidate : info.parts) {
    if (Lower(candidate.name).find("tongue") != std::string::npos && candidate.vertices.last < rig.vertex_count()) {
      part = &candidate;
      break;
    }
  }
  if (!part) return std::nullopt;
  double part_motion = 0.0;
  for (std::uint32_t v = part->vertices.first; v <= part->vertices.last; ++v) {
    part_motion = std::max(part_motion, double(glm::length(jaw[v])));
  }
  std::vector<bool> carried(rig.vertex_count(), false);
  for (std::size_t v = 0; v < carried.size(); ++v) {
    carried[v] = part_motion > 0.0 && glm::length(jaw[v]) >= kCarriedShare * part_motion;
  }
  TongueGeometry tongue;
  tongue.part = part->name;
  for (const TemplatePart& teeth : info.parts) {
    if (RoleOfPart(teeth.name) != PartRole::kTeeth || teeth.vertices.last >= rig.vertex_count()) continue;
    for (std::uint32_t v = teeth.vertices.first; v <= teeth.vertices.last; ++v) {
      if (carried[v]) tongue.lower_teeth.push_back(v);
    }
  }
  if (RoleOfPart(part->name) == PartRole::kTongue) {
    tongue.vertices.resize(part->vertices.count());
    std::iota(tongue.vertices.begin(), tongue.vertices.end(), part->vertices.first);
  } else if (part_motion > 0.0) {  // the tongue shares its part with the gums
    tongue.vertices = PickTongueChart(CarriedCharts(rig, part->vertices, carried), tongue.lower_teeth, rig, up);
  }
  if (tongue.vertices.empty()) return std::nullopt;
  return tongue;
}

// The tongue's forward direction: from its centroid towards the skin vertex
// the jaw moves most (the chin), across the up axis.
std::optional<glm::dvec3> TongueForward(const std::vector<glm::dvec3>& posed, const std::vector<glm::vec3>& jaw,
                                        const FaceTemplateInfo& info, const std::vector<std::uint32_t>& tongue,
                                        const glm::dvec3& up) {
  std::uint32_t chin = info.region.first;
  for (std::uint32_t v = info.region.first; v <= info.region.last && v < jaw.size(); ++v) {
    if (glm::length(jaw[v]) > glm::length(jaw[chin])) chin = v;
  }
  glm::dvec3 centroid(0.0);
  for (std::uint32_t v : tongue) centroid += posed[v];
  centroid /= double(tongue.size());
  glm::dvec3 forward = posed[chin] - centroid;
  forward -= glm::dot(forward, up) * up;
  if (!(glm::length(forward) > 0.0)) return std::nullopt;
  return glm::normalize(forward);
}

// The tongue along its forward axis: its back, its front (the tip's) and the tip.
struct TongueSpan {
  double back = std::numeric_limits<double>::infinity();
  double front = -std::numeric_limits<double>::infinity();
  double length = 0.0;
  std::uint32_t tip = 0;
};

TongueSpan SpanOf(const std::vector<std::uint32_t>& tongue, const std::vector<glm::dvec3>& posed, const Frame& frame) {
  TongueSpan span;
  for (std::uint32_t v : tongue) {
    const double ahead = glm::dot(posed[v], frame.forward);
    span.back = std::min(span.back, ahead);
    if (ahead > span.front) {
      span.front = ahead;
      span.tip = v;
    }
  }
  span.length = span.front - span.back;
  return span;
}

// Where the tongue goes: the lower front teeth (their front, lingual side and
// edge) and the lips' front (the foremost skin the jaw carries: the lower
// lip, the chin), along forward and up.
struct MouthFront {
  bool over_teeth = false;
  double teeth = 0.0, lingual = std::numeric_limits<double>::infinity(), edge = 0.0, lips = 0.0;
};

MouthFront MouthFrontOf(const TongueGeometry& tongue, const FaceTemplateInfo& info, const std::vector<glm::vec3>& jaw,
                        const std::vector<glm::dvec3>& posed, const Frame& frame, const TongueSpan& span) {
  const auto ahead = [&](std::uint32_t v) { return glm::dot(posed[v], frame.forward); };
  MouthFront mouth;
  mouth.teeth = span.front;
  mouth.edge = glm::dot(posed[span.tip], frame.up);
  mouth.over_teeth = !tongue.lower_teeth.empty();
  if (mouth.over_teeth) {
    for (std::uint32_t v : tongue.lower_teeth) mouth.teeth = std::max(mouth.teeth, ahead(v));
    mouth.edge = -std::numeric_limits<double>::infinity();
    for (std::uint32_t v : tongue.lower_teeth) {
      if (ahead(v) < mouth.teeth - 0.1 * span.length) continue;
      mouth.edge = std::max(mouth.edge, glm::dot(posed[v], frame.up));
      mouth.lingual = std::min(mouth.lingual, ahead(v));
    }
  }
  double jaw_motion = 0.0;
  for (std::uint32_t v = info.region.first; v <= info.region.last && v < jaw.size(); ++v) {
    jaw_motion = std::max(jaw_motion, double(glm::length(jaw[v])));
  }
  mouth.lips = mouth.teeth;
  for (std::uint32_t v = info.region.first; v <= info.region.last && v < jaw.size(); ++v) {
    if (glm::length(jaw[v]) >= kCarriedShare * jaw_motion) mouth.lips = std::max(mouth.lips, ahead(v));
  }
  return mouth;
}

// The normals' change, when the rig carries normal deltas.
std::vector<glm::vec3> NormalDeltas(const Rig& rig, const std::vector<glm::vec3>& deltas) {
  if (!rig.has_normal_deltas()) return {};
  const auto rest = rig.positions();
  std::vector<glm::vec3> moved(rest.size()), before(rest.size()), after(rest.size());
  for (std::size_t v = 0; v < rest.size(); ++v) moved[v] = rest[v] + deltas[v];
  ComputeVertexNormals(rest, rig.triangles(), before);
  ComputeVertexNormals(moved, rig.triangles(), after);
  for (std::size_t v = 0; v < rest.size(); ++v) after[v] -= before[v];
  return after;
}

}  // namespace

std::optional<SynthesisedTongueOut> SynthesiseTongueOut(const Rig& rig, const FaceTemplateInfo& info,
                                                        const TongueOutParams& params) {
  if (!FindShapesByArkitName(rig, "tongueOut").empty()) return std::nullopt;
  const std::vector<std::size_t> jaw_shapes = FindShapesByArkitName(rig, "jawOpen");
  if (jaw_shapes.empty()) return std::nullopt;
  const std::vector<glm::vec3> jaw = DenseDeltas(rig, jaw_shapes.front());
  const glm::dvec3 up = rig.up_axis() == UpAxis::kZ ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  const std::optional<TongueGeometry> tongue = FindTongue(rig, info, jaw, up);
  if (!tongue) return std::nullopt;

  const auto rest = rig.positions();
  std::vector<glm::dvec3> posed(rest.size());  // the jaw a little open
  for (std::size_t v = 0; v < rest.size(); ++v) posed[v] = glm::dvec3(rest[v]) + params.jaw_share * glm::dvec3(jaw[v]);
  const std::optional<glm::dvec3> forward = TongueForward(posed, jaw, info, tongue->vertices, up);
  if (!forward) return std::nullopt;
  const Frame frame{*forward, up};
  const TongueSpan span = SpanOf(tongue->vertices, posed, frame);
  if (!(span.length > 0.0)) return std::nullopt;
  const MouthFront mouth = MouthFrontOf(*tongue, info, jaw, posed, frame, span);

  const double reach = mouth.lips + params.overhang * span.length - span.front;
  const double tip_height = glm::dot(posed[span.tip], up);
  const double lift = mouth.over_teeth ? std::max(0.0, mouth.edge + params.clearance * span.length - tip_height) : 0.0;
  const double resting_height = mouth.edge + 0.5 * params.clearance * span.length;
  std::vector<glm::vec3> deltas(rest.size());
  for (std::size_t v = 0; v < rest.size(); ++v) deltas[v] = static_cast<float>(params.jaw_share) * jaw[v];
  for (std::uint32_t v : tongue->vertices) {
    const double along = std::clamp((glm::dot(posed[v], frame.forward) - span.back) / span.length, 0.0, 1.0);
    glm::dvec3 p = posed[v] + along * along * (reach * frame.forward + lift * up);
    // What would end up in the lower front teeth rests on their edge.
    const double height = glm::dot(p, up);
    if (mouth.over_teeth && along > 0.0 && glm::dot(p, frame.forward) >= mouth.lingual && height < resting_height) {
      p += (resting_height - height) * up;
    }
    deltas[v] = glm::vec3(p - glm::dvec3(rest[v]));
  }

  SynthesisedTongueOut result;
  const float drop = 1e-6f * rig.bounding_diagonal();
  result.shape = MakeSparseShape("tongueOut", deltas, NormalDeltas(rig, deltas), drop, 1e-4f);
  result.part = tongue->part;
  result.tongue_vertices = tongue->vertices.size();
  result.tip_vertex = span.tip;
  result.tongue_length = span.length;
  result.forward = glm::vec3(frame.forward);
  result.up = glm::vec3(up);
  result.over_teeth = mouth.over_teeth;
  return result;
}

std::optional<Rig> WithSynthesisedTongueOut(const Rig& rig, const FaceTemplateInfo& info,
                                            SynthesisedTongueOut* synthesised, const TongueOutParams& params) {
  std::optional<SynthesisedTongueOut> tongue_out = SynthesiseTongueOut(rig, info, params);
  if (!tongue_out) return std::nullopt;
  RawRig raw = RigBuilder::ToRaw(rig);
  raw.shapes.push_back(tongue_out->shape);
  std::string problem;
  std::optional<Rig> with = RigBuilder::Build(raw, &problem);
  if (!with) throw InvalidInputError("the template with a synthesised tongueOut is invalid: " + problem);
  if (synthesised) *synthesised = std::move(*tongue_out);
  return with;
}

}  // namespace facerig
