// Reading recorded speech (WAV, FLAC, Ogg/Vorbis, AIFF, ... through
// libsndfile) and bringing it to another sample rate (libsamplerate): the
// recordings that phoneme_alignment.h aligns to their transcripts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace facerig {

// Longest recording read (an hour; alignment itself stops near 20 minutes),
// most samples per channel (an hour at 48 kHz: 700 MB as floats) and the
// largest file: beyond these the file is refused (IoErrorKind::kAbsurdCount)
// before its samples are decoded.
inline constexpr double kMaxAudioSeconds = 3600.0;
inline constexpr std::int64_t kMaxAudioSamples = std::int64_t{3600} * 48'000;
inline constexpr std::uint64_t kMaxAudioFileBytes = std::uint64_t{1} << 30;
inline constexpr int kMaxAudioSampleRate = 768'000;
inline constexpr int kMaxAudioChannels = 256;

struct AudioClip {
  int sample_rate = 0;         // Hz
  int channels_in_file = 0;    // mixed down to `samples`
  std::vector<float> samples;  // mono, nominally in [-1, 1]

  double duration_seconds() const {
    return sample_rate > 0 ? static_cast<double>(samples.size()) / sample_rate : 0.0;
  }
};

// Reads a whole audio file, every channel averaged into one. The file is read
// through ReadInputFile (regular files only, size checked first), then decoded
// from memory. Throws IoError naming the file: kOpenFailed (missing,
// unreadable, not a regular file), kBadMagic (not an audio format libsndfile
// knows, with its message), kEmpty (no samples), kAbsurdCount (over the
// limits above, or a rate or channel count out of range), kTruncated (fewer
// samples than the header declares), kNonFinite (NaN or Inf samples).
AudioClip ReadAudioFile(const std::filesystem::path& path);
// Same, from the bytes of a file; `name` is only used in error messages.
AudioClip DecodeAudio(std::span<const std::byte> bytes, const std::string& name);

// `samples` at `from_rate` Hz resampled to `to_rate` Hz (band-limited sinc
// interpolation); the same samples when the rates are equal.
// \throw std::invalid_argument for a rate <= 0 or over kMaxAudioSampleRate,
// std::runtime_error if libsamplerate fails.
std::vector<float> ResampleAudio(std::span<const float> samples, int from_rate, int to_rate);

// Floats in [-1, 1] to 16-bit PCM, clipped.
std::vector<std::int16_t> FloatToPcm(std::span<const float> samples);

}  // namespace facerig
