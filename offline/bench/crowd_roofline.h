// facerig-bench crowd: what one character's sparse blend (with blended
// recomputed normals) must move per frame, and the memory roofline of it:
// streaming the same bytes.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/blend_plan.h"

// One character's blend in one frame, as counted from its weights and state.
struct CrowdWork {
  double active_shapes = 0.0;
  double entries = 0.0;          // position deltas of the active shapes (bridged gaps included)
  double moved_vertices = 0.0;   // positions not at rest (BlendWork)
  double normal_entries = 0.0;   // terms of the normal sums: the shapes' and their pairs'
  double shaded_vertices = 0.0;  // normals not at rest

  // The bytes that must move at least: every delta read once (12), and per
  // moved or shaded vertex its rest value read and its output written (24).
  // Adding the deltas into the outputs is cache traffic, not counted.
  double Bytes() const;
};

CrowdWork CountWork(const facerig::BlendPlan& plan, const std::vector<float>& weights,
                    const facerig::BlendState& state);
// The per-field medians over many character-frames.
CrowdWork MedianWork(const std::vector<CrowdWork>& work);

// Streams exactly CrowdWork::Bytes() sequentially: the deltas and rest values
// shared by all characters (as the plan's are), and each character's own
// outputs (as its position and normal buffers are).
class CrowdRoofline {
 public:
  CrowdRoofline(const CrowdWork& work, std::size_t characters);
  // One character's share.
  void Run(std::size_t character);
  // Depends on every output, so that nothing is optimised away.
  float Checksum() const;

 private:
  std::vector<glm::vec3> deltas_, rest_;
  std::vector<std::vector<glm::vec3>> outputs_;  // per character
};
