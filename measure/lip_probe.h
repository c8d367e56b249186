// Measures lip aperture on a rig: the distance between an upper and a lower
// inner-lip midline vertex, blended straight from the weights (two vertices,
// not the whole mesh), for lip-sync quality measurements.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

class LipProbe {
 public:
  // \pre upper, lower < rig.vertex_count().
  LipProbe(const Rig& rig, std::uint32_t upper, std::uint32_t lower);
  // Aperture in rig units for one weight per rig shape.
  float Aperture(std::span<const float> weights) const;

 private:
  std::array<glm::vec3, 2> neutral_{};
  std::vector<std::array<glm::vec3, 2>> shape_deltas_;  // per shape: upper, lower
};

// The inner-lip centre vertices of an ICT-FaceKit-topology rig (landmarks 62
// and 66 of the 68 in the folder's vertex_indices.json); nullopt when the
// folder has no such list. Throws IoError for an unreadable file.
std::optional<std::array<std::uint32_t, 2>> IctInnerLipVertices(const std::filesystem::path& ict_folder);

}  // namespace facerig
