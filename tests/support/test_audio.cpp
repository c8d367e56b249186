#include "support/test_audio.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>

namespace facerig::test {
namespace {

void Append(std::string& out, std::uint32_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFF));
}

}  // namespace

std::string WavBytes(std::span<const std::int16_t> samples, int sample_rate, int channels) {
  const auto data_bytes = static_cast<std::uint32_t>(samples.size() * 2);
  const auto block = static_cast<std::uint32_t>(2 * channels);
  std::string out = "RIFF";
  Append(out, 36 + data_bytes, 4);
  out += "WAVEfmt ";
  Append(out, 16, 4);
  Append(out, 1, 2);  // PCM
  Append(out, static_cast<std::uint32_t>(channels), 2);
  Append(out, static_cast<std::uint32_t>(sample_rate), 4);
  Append(out, static_cast<std::uint32_t>(sample_rate) * block, 4);
  Append(out, block, 2);
  Append(out, 16, 2);
  out += "data";
  Append(out, data_bytes, 4);
  for (std::int16_t s : samples) Append(out, static_cast<std::uint16_t>(s), 2);
  return out;
}

void WriteWav(const std::filesystem::path& path, std::span<const std::int16_t> samples, int sample_rate,
              int channels) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << WavBytes(samples, sample_rate, channels);
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::vector<float> Silence(double seconds, int sample_rate) {
  return std::vector<float>(static_cast<std::size_t>(seconds * sample_rate));
}

std::vector<float> Sine(double hz, double seconds, int sample_rate, float amplitude) {
  std::vector<float> out(static_cast<std::size_t>(std::lround(seconds * sample_rate)));
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = amplitude * static_cast<float>(std::sin(2.0 * std::numbers::pi * hz * static_cast<double>(i) / sample_rate));
  }
  return out;
}

}  // namespace facerig::test
