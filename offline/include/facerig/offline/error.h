// The offline library's errors: one type, OfflineError, with what went wrong
// (what()), what it is about (subject(): a mesh such as "target neutral", a
// parameter, or a file) and, where one value is at fault, that value. The
// subclasses only say which step failed, for callers that react differently.
// Files that cannot be read or written throw the runtime's IoError (error.h
// there), which names the file, line and byte offset. The runtime's per-frame
// code never throws.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace facerig {

class OfflineError : public std::runtime_error {
 public:
  explicit OfflineError(const std::string& message, std::string subject = {}, std::string value = {})
      : std::runtime_error(message), subject_(std::move(subject)), value_(std::move(value)) {}
  const std::string& subject() const { return subject_; }  // empty when the message says it all
  const std::string& value() const { return value_; }      // the offending value as text, or empty

 private:
  std::string subject_;
  std::string value_;
};

// The input mesh or parameters cannot be used (empty mesh, NaN coordinates,
// index out of range, mismatched counts, a bad view, ...).
class InvalidInputError : public OfflineError {
 public:
  using OfflineError::OfflineError;
};

// A mesh given to an offline step cannot be used (mismatched vertex counts,
// out-of-range triangle or anchor indices, non-finite positions). mesh() names
// the input, e.g. "target neutral" or "source expression 3".
class MeshInputError : public InvalidInputError {
 public:
  MeshInputError(std::string mesh, const std::string& message)
      : InvalidInputError(mesh + ": " + message, mesh), mesh_(std::move(mesh)) {}
  const std::string& mesh() const { return mesh_; }

 private:
  std::string mesh_;
};

// The automatic landmark detector found no face; the message suggests a
// landmark file.
class LandmarkDetectionError : public OfflineError {
 public:
  using OfflineError::OfflineError;
};

// A sparse factorization or solve failed (not positive definite, NaN).
class SolverError : public OfflineError {
 public:
  using OfflineError::OfflineError;
};

// The template and the target could not be matched: the registration's
// residual is too large, or the fit had to crush the template (not a face, or
// wrong landmarks). The message gives the residual.
class RegistrationMismatchError : public OfflineError {
 public:
  using OfflineError::OfflineError;
};

}  // namespace facerig
