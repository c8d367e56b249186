// Smooth value noise on a surface's 3D points, for painted textures: a
// hashed lattice, interpolated with a smoothstep, in [-1, 1]. In 3D rather
// than in the texture, whose texels stretch unevenly over the surface.
#pragma once

#include <cstdint>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace facerig {

inline float LatticeValue(int x, int y, int z, std::uint32_t seed) {
  std::uint32_t h = seed;
  for (const int c : {x, y, z}) {
    h ^= static_cast<std::uint32_t>(c) + 0x9e3779b9u + (h << 6) + (h >> 2);
    h *= 0x85ebca6bu;
    h ^= h >> 13;
  }
  return static_cast<float>(h & 0xffffu) / 32767.5f - 1.0f;
}

// `p` in lattice cells (divide a position by the cell size first).
inline float ValueNoise(const glm::vec3& p, std::uint32_t seed) {
  const glm::vec3 base = glm::floor(p);
  glm::vec3 f = p - base;
  f = f * f * (3.0f - 2.0f * f);
  const int x = static_cast<int>(base.x), y = static_cast<int>(base.y), z = static_cast<int>(base.z);
  float value = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    const float w = (dx ? f.x : 1.0f - f.x) * (dy ? f.y : 1.0f - f.y) * (dz ? f.z : 1.0f - f.z);
    value += w * LatticeValue(x + dx, y + dy, z + dz, seed);
  }
  return value;
}

}  // namespace facerig
