#include "facerig/runtime/error.h"

#include <string_view>
#include <utility>

namespace facerig {
namespace {
std::string FormatWhat(const std::string& path, const std::string& message, std::int64_t line,
                       std::int64_t offset) {
  // Appends one piece at a time: GCC 12 warns falsely (-Wrestrict) on
  // chained string concatenation with a literal.
  std::string what;
  what.append(path.empty() ? std::string_view("<memory>") : std::string_view(path));
  if (line > 0) what.append(":").append(std::to_string(line));
  if (offset >= 0) what.append(" (byte ").append(std::to_string(offset)).append(")");
  what.append(": ").append(message);
  return what;
}
}  // namespace

const char* ToString(IoErrorKind kind) {
  switch (kind) {
    case IoErrorKind::kOpenFailed: return "open failed";
    case IoErrorKind::kEmpty: return "empty";
    case IoErrorKind::kTruncated: return "truncated";
    case IoErrorKind::kBadMagic: return "bad magic";
    case IoErrorKind::kUnsupportedVersion: return "unsupported version";
    case IoErrorKind::kChecksumMismatch: return "checksum mismatch";
    case IoErrorKind::kParse: return "parse error";
    case IoErrorKind::kIndexOutOfRange: return "index out of range";
    case IoErrorKind::kNonFinite: return "non-finite value";
    case IoErrorKind::kAbsurdCount: return "absurd count";
    case IoErrorKind::kTopologyMismatch: return "topology mismatch";
    case IoErrorKind::kInvalidRig: return "invalid rig";
    case IoErrorKind::kWriteFailed: return "write failed";
    case IoErrorKind::kUnsupportedFormat: return "unsupported format";
  }
  return "unknown error";
}

IoError::IoError(IoErrorKind kind, std::string path, std::string message, std::int64_t line,
                 std::int64_t offset)
    : std::runtime_error(FormatWhat(path, message, line, offset)),
      kind_(kind),
      path_(std::move(path)),
      message_(std::move(message)),
      line_(line),
      offset_(offset) {}

}  // namespace facerig
