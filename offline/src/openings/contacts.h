// Contacts that a template's expression makes across an opening of its mesh
// (OpeningContact, openings.h): the upper lid meeting the lower lid on a
// blink, the lips meeting on mouthClose. Deformation transfer keeps them
// (deformation_transfer.cpp): per-triangle gradients only say how each lid
// bends, not where the other lid is, so on a target whose eye is shaped
// differently the lids stopped short (a template fitted to a stylized head
// closed to 37% of its opening). FindOpeningMargins takes their ends as the
// template's margins.
//
// The rule (OpeningParams, "Contacts") keeps a lid closing over the eye and
// drops what is not a contact: ICT's mouthClose, made to be added to
// jawOpen, alone moves the lower lip 4 cm up in front of the upper lip to the
// nose (324 pairs, the upper lip in between); skin folding onto itself is
// joined by the surface in between.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/ext/vector_int3.hpp>

#include "facerig/offline/openings/openings.h"
#include "facerig/runtime/rig.h"

namespace facerig {

class ContactFinder {
 public:
  // Per-thread working memory of Find.
  struct Scratch {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;  // (grid cell, vertex), sorted
    std::vector<std::pair<float, std::uint32_t>> candidates;     // (distance, vertex)
    std::vector<float> path_length;                              // #V, +inf where unvisited
    std::vector<std::uint32_t> visited;
    std::vector<std::pair<float, std::uint32_t>> queue;  // (estimate, vertex), a heap
    std::vector<std::uint32_t> triangle_stamp;           // #F: last sight test that saw it
    std::uint32_t sight_test = 0;
  };

  // neutral: the template's rest positions (#V); component_of_vertex: each
  // vertex's connected part (#V). Spans must outlive the finder; params'
  // contact_* fields give the rule.
  ContactFinder(std::span<const glm::vec3> neutral, std::span<const Triangle> triangles,
                std::span<const std::uint32_t> component_of_vertex, const OpeningParams& params = {});

  // The contacts of one expression (#V positions), whose largest vertex
  // motion is largest_motion, into contacts (cleared first). free_index
  // (#V): the solve's unknown of each vertex, -1 where it is placed otherwise
  // (pinned); only vertices with free_index[u] >= 0 are taken as moving ends.
  void Find(std::span<const glm::vec3> expression, float largest_motion,
            std::span<const std::int32_t> free_index, std::vector<OpeningContact>& contacts,
            Scratch& scratch) const;

 private:
  // True when the shortest edge path from u to v at rest is longer than limit.
  bool PathLongerThan(std::uint32_t u, std::uint32_t v, float limit, Scratch& scratch) const;
  // True when the segment from u to v at rest crosses a triangle of their
  // part that contains neither.
  bool SightBlocked(std::uint32_t u, std::uint32_t v, Scratch& scratch) const;
  // True when triangle j of u's part, other than u's and v's, passes within
  // clearance of the middle of the segment from u to v, or crosses it.
  bool TriangleNearSight(std::uint32_t j, std::uint32_t u, std::uint32_t v, float clearance) const;
  // The grid cell of a rest position, clamped to the grid, per axis.
  glm::ivec3 GridCell(glm::vec3 p) const;

  OpeningParams params_;
  std::span<const glm::vec3> neutral_;
  std::span<const Triangle> triangles_;
  std::span<const std::uint32_t> component_of_vertex_;
  std::vector<glm::vec3> triangle_low_;  // each triangle's bounds at rest
  std::vector<glm::vec3> triangle_high_;
  // A uniform grid of the rest triangles' bounds: cell (x, y, z) holds
  // grid_triangles_[grid_begin_[c]..grid_begin_[c + 1]) with c = x + n (y + n z).
  glm::vec3 grid_origin_{0.0f};
  float grid_cell_ = 1.0f;
  int grid_size_ = 1;  // n
  std::vector<std::uint32_t> grid_begin_;
  std::vector<std::uint32_t> grid_triangles_;
  std::vector<std::uint32_t> neighbour_begin_;  // #V + 1, into neighbours_
  std::vector<std::uint32_t> neighbours_;
};

}  // namespace facerig
