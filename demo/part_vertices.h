// The vertices of a rig's parts, for per-vertex attributes set by part
// (iris_radial.h, mouth_light.h).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig::player {

// The vertices of the triangles of every part `which(part)` accepts, sorted,
// each once.
template <typename Which>
std::vector<std::uint32_t> VerticesOfParts(const Rig& rig, Which&& which) {
  std::vector<std::uint32_t> vertices;
  for (const Part& part : rig.parts()) {
    if (!which(part)) continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (std::uint32_t v : rig.triangles()[t]) vertices.push_back(v);
    }
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

}  // namespace facerig::player
