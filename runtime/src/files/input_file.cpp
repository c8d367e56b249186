#include "facerig/runtime/files/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include "facerig/runtime/error.h"

namespace facerig {
namespace {

const char* FileTypeName(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void FailNotRegular(const std::filesystem::path& path, mode_t mode) {
  throw IoError(IoErrorKind::kOpenFailed, path.string(),
                std::string("is ") + FileTypeName(mode) + ", not a regular file");
}

// Closes the descriptor on every path out of ReadWhole.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

// Opens `path` for reading only if it is a regular file. The type is checked
// before opening (opening a FIFO blocks until a writer appears) and again on
// the descriptor, which is opened non-blocking in case the file was swapped
// for a FIFO in between. Returns the descriptor and the file size.
FileDescriptor OpenRegularFile(const std::filesystem::path& path, std::uint64_t* size) {
  struct stat before {};
  if (::stat(path.c_str(), &before) != 0) {
    throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
  }
  if (!S_ISREG(before.st_mode)) FailNotRegular(path, before.st_mode);
  FileDescriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (file.get() < 0) throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
  struct stat opened {};
  if (::fstat(file.get(), &opened) != 0) {
    throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
  }
  if (!S_ISREG(opened.st_mode)) FailNotRegular(path, opened.st_mode);
  const int flags = ::fcntl(file.get(), F_GETFL);
  if (flags < 0 || ::fcntl(file.get(), F_SETFL, flags & ~O_NONBLOCK) != 0) {
    throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
  }
  *size = static_cast<std::uint64_t>(opened.st_size);
  return file;
}

template <typename Buffer>
Buffer ReadWhole(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::uint64_t size = 0;
  const FileDescriptor file = OpenRegularFile(path, &size);
  if (size > max_bytes) {
    throw IoError(IoErrorKind::kAbsurdCount, path.string(),
                  "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                      std::to_string(max_bytes));
  }
  Buffer buffer(static_cast<std::size_t>(size), {});
  std::size_t done = 0;
  while (done < buffer.size()) {
    const ssize_t got = ::read(file.get(), buffer.data() + done, buffer.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
    if (got == 0) {
      throw IoError(IoErrorKind::kTruncated, path.string(),
                    "short read (" + std::to_string(done) + " of " + std::to_string(size) + " bytes)");
    }
    done += static_cast<std::size_t>(got);
  }
  return buffer;
}

}  // namespace

bool IsInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder) {
  const std::filesystem::path relative = path.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

std::vector<std::byte> ReadInputFile(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadWhole<std::vector<std::byte>>(path, max_bytes);
}

std::string ReadInputText(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadWhole<std::string>(path, max_bytes);
}

std::filesystem::path ResolveInsideFolder(const std::filesystem::path& file, std::string_view reference,
                                          std::string_view field) {
  auto fail = [&](const std::string& why) -> std::filesystem::path {
    throw IoError(IoErrorKind::kOpenFailed, file.string(),
                  std::string(field) + ": '" + QuoteInput(reference) + "' " + why);
  };
  if (reference.empty()) return fail("is empty");
  if (reference.find('\0') != std::string_view::npos) return fail("contains a NUL byte");
  const std::filesystem::path named(reference);
  if (named.has_root_path()) return fail("is an absolute path (only paths inside the file's folder are read)");
  std::error_code error;
  std::filesystem::path folder = std::filesystem::absolute(file, error).parent_path();
  if (error) return fail("cannot be resolved: " + error.message());
  const std::filesystem::path lexical = (folder / named).lexically_normal();
  if (!IsInsideFolder(lexical, folder.lexically_normal())) {
    return fail("leads outside the file's folder (through '..')");
  }
  folder = std::filesystem::weakly_canonical(folder, error);
  std::filesystem::path target;
  if (!error) target = std::filesystem::weakly_canonical(folder / named, error);
  if (error) return fail("cannot be resolved: " + error.message());
  if (!IsInsideFolder(target, folder)) return fail("leads outside the file's folder (through a symbolic link)");
  return target;
}

void CheckJsonNesting(std::string_view text, const std::string& path, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character, whatever it is
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      if (++depth > max_depth) {
        throw IoError(IoErrorKind::kParse, path,
                      "JSON nested deeper than " + std::to_string(max_depth) + " levels", 0,
                      static_cast<std::int64_t>(i));
      }
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
  }
}

std::string QuoteInput(std::string_view text, std::size_t max_bytes) {
  const bool cut = text.size() > max_bytes;
  std::string quoted(text.substr(0, max_bytes));
  for (char& c : quoted) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte >= 0x7F) c = '?';
  }
  if (cut) quoted += "...";
  return quoted;
}

}  // namespace facerig
