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

// The sample rate of most test signals (the aligner's and the rough mode's usual input).
inline constexpr int kSpeechRate = 16000;

// `seconds` of silence.
std::vector<float> Silence(double seconds, int sample_rate = kSpeechRate);

// `seconds` of a sine at `hz`, amplitude `amplitude` (of full scale).
std::vector<float> Sine(double hz, double seconds, int sample_rate, float amplitude = 0.5f);

}  // namespace facerig::test
