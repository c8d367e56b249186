// Typed errors for facerig's readers, writers and importers.
//
// Loading and saving report failures by throwing IoError; the per-frame path
// (jobs) never throws and reports by return value instead.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace facerig {

enum class IoErrorKind {
  kOpenFailed,          // file missing or unreadable
  kEmpty,               // zero bytes, or no geometry at all
  kTruncated,           // the data ends before a declared size
  kBadMagic,            // not the format the extension claims
  kUnsupportedVersion,  // a .frig (or other) version this build cannot read
  kChecksumMismatch,    // stored checksum differs from the data
  kParse,               // malformed text or structure
  kIndexOutOfRange,     // a face / shape / part index outside its array
  kNonFinite,           // NaN or Inf in positions, deltas, UVs or normals
  kAbsurdCount,         // a declared count that cannot fit in the file
  kTopologyMismatch,    // an expression mesh whose topology differs from the neutral
  kInvalidRig,          // data that RigBuilder refuses (see RawRig::Validate)
  kWriteFailed,         // could not write or rename the output
  kUnsupportedFormat,   // unknown file extension
};

const char* ToString(IoErrorKind kind);

// An error about one file. `line` is 1-based (0 when unknown or not a text
// format); `offset` is a byte offset (-1 when unknown).
class IoError : public std::runtime_error {
 public:
  IoError(IoErrorKind kind, std::string path, std::string message, std::int64_t line = 0,
          std::int64_t offset = -1);

  IoErrorKind kind() const { return kind_; }
  const std::string& path() const { return path_; }
  std::int64_t line() const { return line_; }
  std::int64_t offset() const { return offset_; }
  // The message alone, without the "path:line:" prefix that what() carries.
  const std::string& message() const { return message_; }

 private:
  IoErrorKind kind_;
  std::string path_;
  std::string message_;
  std::int64_t line_;
  std::int64_t offset_;
};

}  // namespace facerig
