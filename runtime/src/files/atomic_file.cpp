#include "facerig/runtime/files/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"

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

}  // namespace

void WriteFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  WriteBytes(path, bytes.data(), bytes.size());
}

void WriteFileAtomically(const std::filesystem::path& path, std::string_view text) {
  WriteBytes(path, text.data(), text.size());
}

std::vector<std::byte> ReadFileBytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadInputFile(path, max_bytes);
}

std::string ReadFileText(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return ReadInputText(path, max_bytes);
}

}  // namespace facerig
