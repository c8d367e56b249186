// The offline tests' sheet with a slit, the smallest mesh with an opening
// that closes (an eye on a blink): an 11 x 7 vertex grid in the XY plane with
// unit spacing, vertex x + 11 y at (x, y, 0), and a hole between rows 3 and 4
// from x = 2 to x = 8.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig::test {

// Its dimensions and vertex numbering (`using namespace facerig::test::slit;`).
namespace slit {
inline constexpr std::uint32_t kColumns = 11;  // x = 0..10
inline constexpr std::uint32_t kRows = 7;      // y = 0..6
inline constexpr std::uint32_t kSlitRow = 3;   // the slit lies between rows 3 and 4 ...
inline constexpr std::uint32_t kSlitFirst = 2;  // ... from x = 2 to x = 8
inline constexpr std::uint32_t kSlitLast = 8;
constexpr std::uint32_t Vertex(std::uint32_t x, std::uint32_t y) { return x + kColumns * y; }
}  // namespace slit

using SlitSheet = Mesh;

// with_slit false: the same sheet without the hole. row_y: each row's height
// (empty: y).
inline SlitSheet MakeSlitSheet(bool with_slit = true, std::span<const float> row_y = {}) {
  SlitSheet sheet;
  for (std::uint32_t y = 0; y < slit::kRows; ++y) {
    const float height = row_y.empty() ? static_cast<float>(y) : row_y[y];
    for (std::uint32_t x = 0; x < slit::kColumns; ++x) sheet.positions.emplace_back(x, height, 0.0f);
  }
  for (std::uint32_t y = 0; y + 1 < slit::kRows; ++y) {
    for (std::uint32_t x = 0; x + 1 < slit::kColumns; ++x) {
      if (with_slit && y == slit::kSlitRow && x >= slit::kSlitFirst && x < slit::kSlitLast) continue;
      sheet.triangles.push_back({slit::Vertex(x, y), slit::Vertex(x + 1, y), slit::Vertex(x + 1, y + 1)});
      sheet.triangles.push_back({slit::Vertex(x, y), slit::Vertex(x + 1, y + 1), slit::Vertex(x, y + 1)});
    }
  }
  return sheet;
}

// A blink's deltas: between the slit's ends, its upper edge comes down by
// 0.98 (stopping 0.02 above the lower edge) and the row above it by half.
inline std::vector<glm::vec3> SlitBlinkDeltas() {
  std::vector<glm::vec3> deltas(slit::kColumns * slit::kRows, glm::vec3(0.0f));
  for (std::uint32_t x = slit::kSlitFirst + 1; x < slit::kSlitLast; ++x) {
    deltas[slit::Vertex(x, slit::kSlitRow + 1)].y = -0.98f;
    deltas[slit::Vertex(x, slit::kSlitRow + 2)].y = -0.49f;
  }
  return deltas;
}

}  // namespace facerig::test
