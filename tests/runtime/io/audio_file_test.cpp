// Recordings read through libsndfile from ReadInputFile's bytes, and resampled.
#include "facerig/runtime/io/audio_file.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "support/test_audio.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

void WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

IoErrorKind ReadErrorKind(const fs::path& path) {
  try {
    ReadAudioFile(path);
  } catch (const IoError& e) {
    CHECK_THAT(e.what(), Contains(path.string()));
    return e.kind();
  }
  FAIL("no error for " << path);
  return IoErrorKind::kParse;
}

// Sign changes per second of `samples`: twice a sine's frequency.
double ZeroCrossingRate(const std::vector<float>& samples, int sample_rate) {
  std::size_t crossings = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) crossings += (samples[i - 1] < 0.0f) != (samples[i] < 0.0f);
  return static_cast<double>(crossings) * sample_rate / static_cast<double>(samples.size());
}

TEST_CASE("ReadAudioFile: a mono 16-bit WAV reads back sample for sample", "[audio_file]") {
  const std::vector<std::int16_t> samples = {0, 1000, -1000, 32767, -32768, 5};
  const fs::path path = test::OutputPath("audio_mono.wav");
  test::WriteWav(path, samples, 16000);
  const AudioClip clip = ReadAudioFile(path);
  CHECK(clip.sample_rate == 16000);
  CHECK(clip.channels_in_file == 1);
  REQUIRE(clip.samples.size() == samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) CHECK(clip.samples[i] == Approx(samples[i] / 32768.0).margin(1e-6));
  CHECK(FloatToPcm(clip.samples) == samples);
}

TEST_CASE("ReadAudioFile: stereo is averaged into mono", "[audio_file]") {
  const std::vector<std::int16_t> interleaved = {1000, 3000, -2000, 0, 400, 400};
  const fs::path path = test::OutputPath("audio_stereo.wav");
  test::WriteWav(path, interleaved, 44100, 2);
  const AudioClip clip = ReadAudioFile(path);
  CHECK(clip.channels_in_file == 2);
  REQUIRE(clip.samples.size() == 3);
  CHECK(clip.samples[0] == Approx(2000 / 32768.0));
  CHECK(clip.samples[1] == Approx(-1000 / 32768.0));
  CHECK(clip.duration_seconds() == Approx(3.0 / 44100));
}

TEST_CASE("ReadAudioFile: bad files are IoErrors naming the file, never a crash", "[audio_file]") {
  const fs::path missing = test::OutputPath("audio_missing.wav");
  fs::remove(missing);
  CHECK(ReadErrorKind(missing) == IoErrorKind::kOpenFailed);
  const fs::path folder = test::OutputPath("audio_folder.wav");
  fs::create_directories(folder);
  CHECK(ReadErrorKind(folder) == IoErrorKind::kOpenFailed);
  const fs::path empty = test::OutputPath("audio_empty.wav");
  WriteBytes(empty, "");
  CHECK(ReadErrorKind(empty) == IoErrorKind::kEmpty);
  const fs::path text = test::OutputPath("audio_text.wav");
  WriteBytes(text, "this is not audio at all, just some words in a file");
  CHECK(ReadErrorKind(text) == IoErrorKind::kBadMagic);
  // A header and no samples.
  const fs::path no_samples = test::OutputPath("audio_no_samples.wav");
  test::WriteWav(no_samples, std::vector<std::int16_t>{}, 22050);
  CHECK(ReadErrorKind(no_samples) == IoErrorKind::kEmpty);
  // A data chunk that claims 4 GB in a file of a few bytes.
  std::string lying = test::WavBytes(std::vector<std::int16_t>(10, 3), 8000);
  lying[40] = lying[41] = lying[42] = lying[43] = '\xF0';
  const fs::path lying_path = test::OutputPath("audio_lying.wav");
  WriteBytes(lying_path, lying);
  try {
    const std::size_t read = ReadAudioFile(lying_path).samples.size();
    CHECK(read <= 10);
  } catch (const IoError& e) {
    CHECK_THAT(e.what(), Contains(lying_path.string()));
  }
  // Every prefix of a valid file: an error or fewer samples, never a crash.
  const std::string whole = test::WavBytes(std::vector<std::int16_t>(100, 7), 8000);
  const fs::path cut = test::OutputPath("audio_cut.wav");
  for (std::size_t size = 0; size < whole.size(); size += 7) {
    WriteBytes(cut, whole.substr(0, size));
    try {
      const std::size_t read = ReadAudioFile(cut).samples.size();
      CHECK(read < 100);
    } catch (const IoError& e) {
      CHECK_THAT(e.what(), Contains(cut.string()));
    }
  }
}

TEST_CASE("ReadAudioFile: absurd headers are refused before decoding", "[audio_file]") {
  std::string bytes = test::WavBytes(std::vector<std::int16_t>(16, 1), 8000);
  SECTION("a sample rate of 4 GHz") {
    bytes[24] = bytes[25] = bytes[26] = bytes[27] = '\xFF';
  }
  SECTION("a channel count of 60000") {
    bytes[22] = '\x60';
    bytes[23] = '\xEA';
  }
  const fs::path path = test::OutputPath("audio_absurd.wav");
  WriteBytes(path, bytes);
  const IoErrorKind kind = ReadErrorKind(path);
  CHECK((kind == IoErrorKind::kAbsurdCount || kind == IoErrorKind::kBadMagic));
}

TEST_CASE("ResampleAudio: keeps a tone's pitch and the duration", "[audio_file]") {
  const std::vector<float> tone = test::Sine(440.0, 1.0, 44100);
  const std::vector<float> out = ResampleAudio(tone, 44100, 22050);
  CHECK(static_cast<double>(out.size()) == Approx(22050).margin(2));
  CHECK(ZeroCrossingRate(out, 22050) == Approx(880.0).epsilon(0.01));
  CHECK(ResampleAudio(tone, 44100, 44100) == tone);
  CHECK(ResampleAudio({}, 8000, 16000).empty());
  CHECK_THROWS_AS(ResampleAudio(tone, 0, 16000), std::invalid_argument);
  CHECK_THROWS_AS(ResampleAudio(tone, 16000, -5), std::invalid_argument);
}

}  // namespace
}  // namespace facerig
