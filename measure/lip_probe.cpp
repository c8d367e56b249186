#include "measure/lip_probe.h"

#include <algorithm>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/offline/error.h"

namespace facerig {

LipProbe::LipProbe(const Rig& rig, std::uint32_t upper, std::uint32_t lower) {
  if (upper >= rig.vertex_count() || lower >= rig.vertex_count()) {
    throw InvalidInputError("LipProbe: lip vertex outside the rig");
  }
  const std::array<std::uint32_t, 2> vertices = {upper, lower};
  neutral_ = {rig.positions()[upper], rig.positions()[lower]};
  shape_deltas_.assign(rig.shape_count(), {glm::vec3(0.0f), glm::vec3(0.0f)});
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t k = 0; k < 2; ++k) {
      const auto it = std::lower_bound(shape.vertex_indices.begin(), shape.vertex_indices.end(), vertices[k]);
      if (it != shape.vertex_indices.end() && *it == vertices[k]) {
        shape_deltas_[s][k] = shape.position_deltas[static_cast<std::size_t>(it - shape.vertex_indices.begin())];
      }
    }
  }
}

float LipProbe::Aperture(std::span<const float> weights) const {
  std::array<glm::vec3, 2> p = neutral_;
  const std::size_t n = std::min(weights.size(), shape_deltas_.size());
  for (std::size_t s = 0; s < n; ++s) {
    if (weights[s] == 0.0f) continue;
    p[0] += weights[s] * shape_deltas_[s][0];
    p[1] += weights[s] * shape_deltas_[s][1];
  }
  return glm::length(p[0] - p[1]);
}

std::optional<std::array<std::uint32_t, 2>> IctInnerLipVertices(const std::filesystem::path& ict_folder) {
  const std::filesystem::path json_path = ict_folder / "vertex_indices.json";
  if (!std::filesystem::exists(json_path)) return std::nullopt;
  const std::string text = ReadFileText(json_path, 64u << 20);
  CheckJsonNesting(text, json_path.string());
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_object() || !json.contains("idx_to_landmark_verts")) {
    throw IoError(IoErrorKind::kParse, json_path.string(), "no idx_to_landmark_verts list");
  }
  const nlohmann::json& landmarks = json["idx_to_landmark_verts"];
  if (!landmarks.is_array() || landmarks.size() != 68 || !landmarks[62].is_number_unsigned() ||
      !landmarks[66].is_number_unsigned()) {
    throw IoError(IoErrorKind::kParse, json_path.string(), "idx_to_landmark_verts is not 68 vertex indices");
  }
  return std::array<std::uint32_t, 2>{landmarks[62].get<std::uint32_t>(), landmarks[66].get<std::uint32_t>()};
}

}  // namespace facerig
