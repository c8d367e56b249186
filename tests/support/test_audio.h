// Audio for the tests without an audio library: 16-bit PCM WAV bytes and
// simple signals.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace facerig::test {

// A canonical 44-byte-header PCM WAV; `samples` interleaved when channels > 1.
std::string WavBytes(std::span<const std::int16_t> samples, int sample_rate, int channels = 1);
void WriteWav(const std::filesystem::path& path, std::span<const std::int16_t> samples, int sample_rate,
              int channels = 1);

// `seconds` of a sine at `hz`, amplitude `amplitude` (of full scale).
std::vector<float> Sine(double hz, double seconds, int sample_rate, float amplitude = 0.5f);

}  // namespace facerig::test
