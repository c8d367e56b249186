// .frig rigs: each input is parsed as it is, then again with its header's
// file size and CRC-32 made right, so that mutations get past the checksum to
// the sections behind it.
#include <cstring>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/frig.h"
#include "fuzz_input.h"

namespace {

void Parse(std::span<const std::byte> bytes) {
  try {
    facerig::ParseFrig(bytes, "input.frig");
  } catch (const facerig::IoError&) {
  }
}

// The header's file_size (u64 at 16) and crc32 (u32 at 12, of bytes [32, end)), little-endian.
std::vector<std::byte> WithValidChecksum(std::span<const std::byte> bytes) {
  std::vector<std::byte> fixed(bytes.begin(), bytes.end());
  const std::uint64_t size = fixed.size();
  for (int i = 0; i < 8; ++i) fixed[16 + static_cast<std::size_t>(i)] = static_cast<std::byte>(size >> (8 * i));
  const std::uint32_t crc = facerig::Crc32(std::span<const std::byte>(fixed).subspan(32));
  for (int i = 0; i < 4; ++i) fixed[12 + static_cast<std::size_t>(i)] = static_cast<std::byte>(crc >> (8 * i));
  return fixed;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes = facerig::fuzz::Bytes(data, size);
  Parse(bytes);
  if (size >= 32) Parse(WithValidChecksum(bytes));
  return 0;
}
