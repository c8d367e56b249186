#include "facerig/runtime/io/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "facerig/runtime/error.h"

namespace facerig {
namespace {

std::filesystem::path TemporaryPathBeside(const std::filesystem::path& path) {
  std::random_device device;
  std::filesystem::path temp = path;
  temp += ".tmp-" + std::to_string(device() % 1000000u);
  return temp;
}

void WriteBytes(const std::filesystem::path& path, const void* data, std::size_t size) {
  const std::filesystem::path temp = TemporaryPathBeside(path);
  std::FILE* file = std::fopen(temp.c_str(), "wb");
  if (!file) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(),
                  std::string("cannot create temporary file: ") + std::strerror(errno));
  }
  const bool written = size == 0 || std::fwrite(data, 1, size, file) == size;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    std::remove(temp.c_str());
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "could not write all bytes");
  }
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::remove(temp.c_str());
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "cannot rename into place: " + error.message());
  }
}

template <typename Buffer>
Buffer ReadWhole(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw IoError(IoErrorKind::kOpenFailed, path.string(), "is a directory, not a file");
  }
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) {
    throw IoError(IoErrorKind::kOpenFailed, path.string(), std::strerror(errno));
  }
  std::fseek(file, 0, SEEK_END);
  const long size = std::ftell(file);
  std::fseek(file, 0, SEEK_SET);
  if (size < 0) {
    std::fclose(file);
    throw IoError(IoErrorKind::kOpenFailed, path.string(), "cannot determine the file size");
  }
  if (static_cast<std::uint64_t>(size) > max_bytes) {
    std::fclose(file);
    throw IoError(IoErrorKind::kAbsurdCount, path.string(),
                  "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                      std::to_string(max_bytes));
  }
  Buffer buffer(static_cast<std::size_t>(size), {});
  const std::size_t read = size == 0 ? 0 : std::fread(buffer.data(), 1, buffer.size(), file);
  std::fclose(file);
  if (read != buffer.size()) {
    throw IoError(IoErrorKind::kTruncated, path.string(), "short read");
  }
  return buffer;
}

}  // namespace

void WriteFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  WriteBytes(path, bytes.data(), bytes.size());
}

void WriteFileAtomically(const std::filesystem::path& path, std::string_view text) {
  WriteBytes(path, text.data(), text.size());
}

std::vector<std::byte> ReadFileBytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadWhole<std::vector<std::byte>>(path, max_bytes);
}

std::string ReadFileText(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadWhole<std::string>(path, max_bytes);
}

}  // namespace facerig
