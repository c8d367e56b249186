#include "media_writer.h"

#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace facerig::player {
namespace {

void PutU32(std::ofstream& out, std::uint32_t value) {
  const char bytes[4] = {static_cast<char>(value & 0xff), static_cast<char>((value >> 8) & 0xff),
                         static_cast<char>((value >> 16) & 0xff), static_cast<char>(value >> 24)};
  out.write(bytes, 4);
}

void PutU16(std::ofstream& out, std::uint16_t value) {
  const char bytes[2] = {static_cast<char>(value & 0xff), static_cast<char>(value >> 8)};
  out.write(bytes, 2);
}

std::uint32_t GetU32(const unsigned char* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

}  // namespace

void WriteWav(const std::filesystem::path& path, std::span<const std::int16_t> samples,
              int sample_rate) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write WAV " + path.string());
  const auto data_bytes = static_cast<std::uint32_t>(samples.size() * 2);
  out.write("RIFF", 4);
  PutU32(out, 36 + data_bytes);
  out.write("WAVEfmt ", 8);
  PutU32(out, 16);  // PCM fmt chunk size
  PutU16(out, 1);   // PCM
  PutU16(out, 1);   // mono
  PutU32(out, static_cast<std::uint32_t>(sample_rate));
  PutU32(out, static_cast<std::uint32_t>(sample_rate) * 2);  // byte rate
  PutU16(out, 2);                                            // block align
  PutU16(out, 16);                                           // bits per sample
  out.write("data", 4);
  PutU32(out, data_bytes);
  // Little-endian samples, written byte by byte so the file is right on any host.
  std::vector<char> bytes(samples.size() * 2);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto value = static_cast<std::uint16_t>(samples[i]);
    bytes[2 * i] = static_cast<char>(value & 0xff);
    bytes[2 * i + 1] = static_cast<char>(value >> 8);
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write WAV " + path.string());
}

std::vector<std::int16_t> ReadWav(const std::filesystem::path& path, int* sample_rate) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read WAV " + path.string());
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), {});
  if (bytes.size() < 44 || std::memcmp(bytes.data(), "RIFF", 4) != 0 ||
      std::memcmp(bytes.data() + 8, "WAVE", 4) != 0) {
    throw std::runtime_error("not a WAV file: " + path.string());
  }
  std::size_t offset = 12;
  std::vector<std::int16_t> samples;
  while (offset + 8 <= bytes.size()) {
    const std::uint32_t size = GetU32(bytes.data() + offset + 4);
    if (std::memcmp(bytes.data() + offset, "fmt ", 4) == 0 && sample_rate != nullptr) {
      *sample_rate = static_cast<int>(GetU32(bytes.data() + offset + 12));
    }
    if (std::memcmp(bytes.data() + offset, "data", 4) == 0) {
      const std::size_t count = std::min<std::size_t>(size, bytes.size() - offset - 8) / 2;
      samples.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        const unsigned char* p = bytes.data() + offset + 8 + 2 * i;
        samples[i] = static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8)));
      }
      return samples;
    }
    offset += 8 + size + (size & 1);
  }
  throw std::runtime_error("WAV without a data chunk: " + path.string());
}

void WritePng(const std::filesystem::path& path, const Image& image) {
  const cv::Mat rgba(image.height, image.width, CV_8UC4,
                     const_cast<std::uint8_t*>(image.rgba.data()));
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), bgr);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot write PNG " + path.string() + ": " + e.what());
  }
  if (!ok) throw std::runtime_error("cannot write PNG " + path.string());
}

Image ReadPng(const std::filesystem::path& path) {
  const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error("cannot read PNG " + path.string());
  Image image;
  image.width = bgr.cols;
  image.height = bgr.rows;
  image.rgba.resize(static_cast<std::size_t>(image.width) * image.height * 4);
  cv::Mat rgba(image.height, image.width, CV_8UC4, image.rgba.data());
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  return image;
}

}  // namespace facerig::player
