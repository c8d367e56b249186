#include "media_writer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/render/png_encode.h"
#include "facerig/offline/io/image_codec.h"
#include "facerig/runtime/files/image_file.h"
#include "output_set.h"

namespace facerig::player {
namespace {

void PutU32(std::vector<char>& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<char>((value >> shift) & 0xff));
}

void PutU16(std::vector<char>& out, std::uint16_t value) {
  out.push_back(static_cast<char>(value & 0xff));
  out.push_back(static_cast<char>(value >> 8));
}

void PutText(std::vector<char>& out, const char* text) {
  out.insert(out.end(), text, text + std::strlen(text));
}

// The failure injection (FailureInjected) that makes writing `what` run out of space.
bool WriteFailureInjected(const char* what) {
  return (std::strcmp(what, "WAV") == 0 && FailureInjected("wav")) ||
         (std::strcmp(what, "timing JSON") == 0 && FailureInjected("timing"));
}

}  // namespace

void WriteWholeFile(const std::filesystem::path& path, std::span<const char> bytes, const char* what) {
  const auto fail = [&](int error) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    throw std::runtime_error(std::string("cannot write ") + what + " " + path.string() + ": " + std::strerror(error));
  };
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) fail(errno);
  const bool injected = WriteFailureInjected(what);
  const std::size_t size = injected ? bytes.size() / 2 : bytes.size();
  bool ok = std::fwrite(bytes.data(), 1, size, file) == size && std::fflush(file) == 0;
  int error = ok ? 0 : errno;
  if (injected) ok = false, error = ENOSPC;
  if (std::fclose(file) != 0 && ok) ok = false, error = errno;
  if (!ok) fail(error);
}

void WriteWav(const std::filesystem::path& path, std::span<const std::int16_t> samples,
              int sample_rate) {
  const auto data_bytes = static_cast<std::uint32_t>(samples.size() * 2);
  std::vector<char> bytes;
  bytes.reserve(44 + samples.size() * 2);
  PutText(bytes, "RIFF");
  PutU32(bytes, 36 + data_bytes);
  PutText(bytes, "WAVEfmt ");
  PutU32(bytes, 16);  // PCM fmt chunk size
  PutU16(bytes, 1);   // PCM
  PutU16(bytes, 1);   // mono
  PutU32(bytes, static_cast<std::uint32_t>(sample_rate));
  PutU32(bytes, static_cast<std::uint32_t>(sample_rate) * 2);  // byte rate
  PutU16(bytes, 2);                                            // block align
  PutU16(bytes, 16);                                           // bits per sample
  PutText(bytes, "data");
  PutU32(bytes, data_bytes);
  // Little-endian samples, written byte by byte so the file is right on any host.
  for (const std::int16_t sample : samples) PutU16(bytes, static_cast<std::uint16_t>(sample));
  WriteWholeFile(path, bytes, "WAV");
}

void WritePng(const std::filesystem::path& path, const Image& image) {
  const cv::Mat rgba(image.height, image.width, CV_8UC4, const_cast<std::uint8_t*>(image.rgba.data()));
  cv::Mat rgb;  // the frames are opaque: an RGB PNG
  cv::cvtColor(rgba, rgb, cv::COLOR_RGBA2RGB);
  EncodedImage png;
  try {
    png = EncodePng(std::span<const std::uint8_t>(rgb.data, rgb.total() * 3), rgb.cols, rgb.rows, 3,
                    path.filename().string());
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write PNG " + path.string() + ": " + e.what());
  }
  // Encoded in memory and written here, because imwrite does not report a failed close (a full disk).
  WriteWholeFile(path, std::span(reinterpret_cast<const char*>(png.bytes.data()), png.bytes.size()), "PNG");
}

Image ReadPng(const std::filesystem::path& path) {
  cv::Mat bgr;
  try {
    bgr = DecodeImageBytes(ReadImageFile(path).bytes, DecodedChannels::kBgr);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read PNG " + path.string() + ": " + e.what());
  }
  Image image;
  image.width = bgr.cols;
  image.height = bgr.rows;
  image.rgba.resize(static_cast<std::size_t>(image.width) * image.height * 4);
  cv::Mat rgba(image.height, image.width, CV_8UC4, image.rgba.data());
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  return image;
}

}  // namespace facerig::player
