#include "facerig/offline/io/image_codec.h"

#include <cstring>

#include <opencv2/imgproc.hpp>

#include "facerig/offline/error.h"
#include "io/image_codec_internal.h"

namespace facerig {
namespace {

bool StartsWith(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> signature) {
  return bytes.size() >= signature.size() && std::memcmp(bytes.data(), signature.data(), signature.size()) == 0;
}

}  // namespace

cv::Mat DecodeImageBytes(std::span<const std::uint8_t> bytes, DecodedChannels channels) {
  constexpr std::uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  constexpr std::uint8_t kJpeg[] = {0xFF, 0xD8, 0xFF};
  cv::Mat decoded;
  if (StartsWith(bytes, kPng)) {
    decoded = codec::DecodePng(bytes);
    if (channels == DecodedChannels::kBgra) return decoded;
    cv::cvtColor(decoded, decoded, cv::COLOR_BGRA2BGR);
    return decoded;
  }
  if (StartsWith(bytes, kJpeg)) {
    decoded = codec::DecodeJpeg(bytes);
    if (channels == DecodedChannels::kBgr) return decoded;
    cv::cvtColor(decoded, decoded, cv::COLOR_BGR2BGRA);
    return decoded;
  }
  throw InvalidInputError("the image is neither PNG nor JPEG");
}

}  // namespace facerig
