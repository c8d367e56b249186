// Still pinning's rigid parts: where the template moves a part's unpinned
// vertices as one rigid body, the target's move by the same rotation.
#include "transfer/deformation_transfer_impl.h"

#include <utility>

namespace facerig {
namespace {

// Sum of |R x + t - x'|^2 and of |x' - x|^2 over vertices (x rest, x' moved).
std::pair<double, double> RigidFitError(std::span<const glm::vec3> rest_positions,
                                        std::span<const glm::vec3> moved_positions,
                                        const SimilarityTransform& fit,
                                        std::span<const std::uint32_t> vertices) {
  double residual2 = 0.0;
  double motion2 = 0.0;
  for (std::uint32_t v : vertices) {
    const Eigen::Vector3d rest = ToEigen(rest_positions[v]);
    const Eigen::Vector3d moved = ToEigen(moved_positions[v]);
    residual2 += (fit.rotation * rest + fit.translation - moved).squaredNorm();
    motion2 += (moved - rest).squaredNorm();
  }
  return std::pair{residual2, motion2};
}

// Parts that move by the same rigid motion (ICT: lower teeth, gums and
// tongue with the jaw) move together, so they keep their places relative
// to each other on the target: each fit's group is the first fit whose
// motion also fits its vertices.
void GroupRigidFits(std::span<const glm::vec3> source_neutral, std::span<const glm::vec3> expression,
                    double tolerance2, std::vector<DeformationTransferData::Impl::Scratch::RigidFit>& fits) {
  for (std::size_t i = 0; i < fits.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (fits[j].group != j) continue;
      const auto [residual2, motion2] =
          RigidFitError(source_neutral, expression, fits[j].transform, fits[i].vertices);
      if (residual2 <= tolerance2 * motion2) {
        fits[i].group = j;
        break;
      }
    }
  }
}

}  // namespace

void DeformationTransferData::Impl::PinRigidMotions(std::span<const glm::vec3> expression,
                                                    std::vector<glm::vec3>& out,
                                                    Scratch& scratch) const {
  FitRigidParts(expression, scratch);
  GroupRigidFits(source_neutral, expression, rigid_tolerance * rigid_tolerance, scratch.rigid_fits);
  PlaceRigidGroups(expression, out, scratch);
}

void DeformationTransferData::Impl::FitRigidParts(std::span<const glm::vec3> expression,
                                                  Scratch& scratch) const {
  const double tolerance2 = rigid_tolerance * rigid_tolerance;
  scratch.rigid_fits.clear();
  for (const std::vector<std::uint32_t>& part : component_members) {
    scratch.moving.clear();
    for (std::uint32_t v : part) {
      if (!scratch.pinned[v]) scratch.moving.push_back(v);
    }
    if (scratch.moving.size() < 4) continue;
    SimilarityTransform fit;
    try {
      fit = FitRigid(source_neutral, expression, scratch.moving);
    } catch (const InvalidInputError&) {
      continue;  // the part's free vertices coincide: no rigid motion to keep
    }
    const auto [residual2, motion2] = RigidFitError(source_neutral, expression, fit, scratch.moving);
    if (fit.rotation.allFinite() && motion2 > 0.0 && residual2 <= tolerance2 * motion2) {
      scratch.rigid_fits.push_back({fit, scratch.moving, scratch.rigid_fits.size()});
    }
  }
}

void DeformationTransferData::Impl::PlaceRigidGroups(std::span<const glm::vec3> expression,
                                                     std::vector<glm::vec3>& out,
                                                     Scratch& scratch) const {
  // Each group: the template's rotation about the group's centroid on the
  // target, and the template's mean displacement.
  const std::vector<Scratch::RigidFit>& fits = scratch.rigid_fits;
  for (std::size_t g = 0; g < fits.size(); ++g) {
    if (fits[g].group != g) continue;
    Eigen::Vector3d target_centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
    std::size_t count = 0;
    for (const Scratch::RigidFit& fit : fits) {
      if (fit.group != g) continue;
      for (std::uint32_t v : fit.vertices) {
        target_centroid += ToEigen(target_neutral[v]);
        displacement += ToEigen(expression[v]) - ToEigen(source_neutral[v]);
      }
      count += fit.vertices.size();
    }
    target_centroid /= static_cast<double>(count);
    const Eigen::Vector3d shift =
        target_centroid + displacement_scale * displacement / static_cast<double>(count);
    const Eigen::Matrix3d rotation = fits[g].transform.rotation;
    for (const Scratch::RigidFit& fit : fits) {
      if (fit.group != g) continue;
      for (std::uint32_t v : fit.vertices) {
        const Eigen::Vector3d p = rotation * (ToEigen(target_neutral[v]) - target_centroid) + shift;
        out[v] = glm::vec3(static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()));
        scratch.pinned[v] = kPinnedRigid;
      }
    }
  }
}

}  // namespace facerig
