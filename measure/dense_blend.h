// The dense reference for blend evaluation: every shape stored as a full
// column of a (3V x S) matrix, evaluated as one matrix-vector product.
// Used to check BlendJob and as the benchmark's baseline; not for real time
// (it reads all 3V x S floats every frame whatever the weights).
#pragma once

#include <span>

#include <Eigen/Core>

#include "facerig/runtime/rig.h"

namespace facerig {

struct DenseBlendShapes {
  Eigen::VectorXf neutral;  // 3V: x0 y0 z0 x1 ...
  Eigen::MatrixXf deltas;   // 3V x S, column s = shape s's delta of every vertex
};

DenseBlendShapes MakeDenseBlendShapes(const Rig& rig);

// out (3V) = neutral + deltas * weights. \pre weights.size() == S.
void DenseBlend(const DenseBlendShapes& dense, std::span<const float> weights, Eigen::VectorXf& out);

}  // namespace facerig
