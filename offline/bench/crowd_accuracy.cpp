#include "bench/crowd_accuracy.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "facerig/runtime/blend_job.h"

namespace {

constexpr double kSmoothDegrees = 30.0;

double Degrees(const glm::vec3& a, const glm::vec3& b) {
  if (a == b) return 0.0;
  return std::acos(std::clamp(static_cast<double>(glm::dot(a, b)), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

}  // namespace

NormalAccuracy::NormalAccuracy(const facerig::Rig& rig)
    : rig_(rig), positions_(rig.vertex_count()), normals_(rig.vertex_count()), crease_cosine_(rig.vertex_count()) {}

void NormalAccuracy::Add(std::span<const float> weights, std::span<const glm::vec3> blended_normals) {
  const facerig::BlendJob recompute{&rig_, weights, facerig::NormalMode::kRecompute, positions_, normals_};
  (void)recompute.Run();
  std::fill(crease_cosine_.begin(), crease_cosine_.end(), 1.0f);
  for (const facerig::Triangle& t : rig_.triangles()) {
    const glm::vec3 n = glm::cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]);
    if (glm::dot(n, n) == 0.0f) continue;
    const glm::vec3 face = glm::normalize(n);
    for (std::uint32_t v : t) crease_cosine_[v] = std::min(crease_cosine_[v], glm::dot(face, normals_[v]));
  }
  const auto smooth_cosine = static_cast<float>(std::cos(kSmoothDegrees * 3.14159265358979323846 / 180.0));
  for (std::size_t v = 0; v < normals_.size(); ++v) {
    const double angle = Degrees(blended_normals[v], normals_[v]);
    worst_ = std::max(worst_, angle);
    ++samples_;
    if (crease_cosine_[v] >= smooth_cosine) {
      worst_smooth_ = std::max(worst_smooth_, angle);
      ++smooth_samples_;
    }
  }
}

double NormalAccuracy::smooth_share() const {
  return samples_ == 0 ? 0.0 : static_cast<double>(smooth_samples_) / static_cast<double>(samples_);
}
