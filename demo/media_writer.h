// Writing the headless player's output: 16-bit mono WAV and PNG frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace facerig::player {

// An 8-bit RGBA image, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4
};

// Writes all of `bytes` to a new file at `path`; a short write or a failed flush
// or close (a full disk) removes the file and throws std::runtime_error "cannot
// write `what` PATH: reason". The failure injections "wav" (for what = "WAV") and
// "timing" (for "timing JSON") stop half-way with ENOSPC (output_set.h).
void WriteWholeFile(const std::filesystem::path& path, std::span<const char> bytes, const char* what);

// Writes exactly `samples` as a 16-bit PCM mono WAV. On any write error (a full disk: a
// short write, a failed flush or close) removes the file and throws std::runtime_error
// "cannot write WAV PATH: reason".
void WriteWav(const std::filesystem::path& path, std::span<const std::int16_t> samples,
              int sample_rate);

// Writes the image as an RGB PNG (OpenCV imgcodecs). Like WriteWav, a write error removes
// the file and throws std::runtime_error "cannot write PNG PATH: reason".
void WritePng(const std::filesystem::path& path, const Image& image);
// Reads a PNG into RGBA. Throws std::runtime_error with the path.
Image ReadPng(const std::filesystem::path& path);

}  // namespace facerig::player
