// Typed errors of the registration pipeline (landmarks, rigid alignment,
// non-rigid ICP). Offline code only: the runtime reports by return value.
#pragma once

#include <stdexcept>
#include <string>

namespace facerig {

// The input mesh or parameters cannot be used (empty mesh, NaN coordinates,
// index out of range, mismatched landmark counts, ...).
class InvalidInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The automatic landmark detector found no face; the message suggests a
// landmark file.
class LandmarkDetectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A sparse factorization or solve failed (not positive definite, NaN).
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace facerig
