#include "measure/dense_blend.h"
#include "facerig/offline/error.h"

#include <stdexcept>

namespace facerig {

DenseBlendShapes MakeDenseBlendShapes(const Rig& rig) {
  const auto rows = static_cast<Eigen::Index>(3 * rig.vertex_count());
  const auto cols = static_cast<Eigen::Index>(rig.shape_count());
  DenseBlendShapes dense;
  dense.neutral.resize(rows);
  for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
    for (int c = 0; c < 3; ++c) dense.neutral(static_cast<Eigen::Index>(3 * v) + c) = rig.positions()[v][c];
  }
  dense.deltas = Eigen::MatrixXf::Zero(rows, cols);
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        dense.deltas(static_cast<Eigen::Index>(3 * shape.vertex_indices[i]) + c,
                     static_cast<Eigen::Index>(s)) = shape.position_deltas[i][c];
      }
    }
  }
  return dense;
}

void DenseBlend(const DenseBlendShapes& dense, std::span<const float> weights, Eigen::VectorXf& out) {
  if (static_cast<Eigen::Index>(weights.size()) != dense.deltas.cols()) {
    throw InvalidInputError("DenseBlend: weight count differs from the shape count");
  }
  const Eigen::Map<const Eigen::VectorXf> w(weights.data(), static_cast<Eigen::Index>(weights.size()));
  out.noalias() = dense.neutral;
  out.noalias() += dense.deltas * w;
}

}  // namespace facerig
