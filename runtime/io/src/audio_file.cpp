#include "facerig/runtime/io/audio_file.h"

#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

// The file's bytes as libsndfile's virtual I/O: decoding from memory keeps
// every open on ReadInputFile's checks (no FIFOs, size known first).
struct MemoryFile {
  std::span<const std::byte> bytes;
  sf_count_t position = 0;
};

sf_count_t Length(void* user) { return static_cast<sf_count_t>(static_cast<MemoryFile*>(user)->bytes.size()); }

sf_count_t Seek(sf_count_t offset, int whence, void* user) {
  auto* file = static_cast<MemoryFile*>(user);
  const auto size = static_cast<sf_count_t>(file->bytes.size());
  const sf_count_t base = whence == SEEK_CUR ? file->position : whence == SEEK_END ? size : 0;
  if (offset > size - base || base + offset < 0) return -1;
  file->position = base + offset;
  return file->position;
}

sf_count_t Read(void* destination, sf_count_t count, void* user) {
  auto* file = static_cast<MemoryFile*>(user);
  const auto size = static_cast<sf_count_t>(file->bytes.size());
  const sf_count_t n = std::clamp<sf_count_t>(size - file->position, 0, std::max<sf_count_t>(count, 0));
  if (n > 0) std::memcpy(destination, file->bytes.data() + file->position, static_cast<std::size_t>(n));
  file->position += n;
  return n;
}

sf_count_t Write(const void*, sf_count_t, void*) { return 0; }
sf_count_t Tell(void* user) { return static_cast<MemoryFile*>(user)->position; }

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};

void CheckHeader(const SF_INFO& info, const std::string& name) {
  if (info.samplerate <= 0 || info.samplerate > kMaxAudioSampleRate) {
    throw IoError(IoErrorKind::kAbsurdCount, name, "sample rate " + std::to_string(info.samplerate) +
                                                       " Hz is out of range (1.." + std::to_string(kMaxAudioSampleRate) + ")");
  }
  if (info.channels <= 0 || info.channels > kMaxAudioChannels) {
    throw IoError(IoErrorKind::kAbsurdCount, name, std::to_string(info.channels) + " channels (at most " +
                                                       std::to_string(kMaxAudioChannels) + ")");
  }
  if (info.frames <= 0) throw IoError(IoErrorKind::kEmpty, name, "the file holds no audio samples");
  if (static_cast<double>(info.frames) > kMaxAudioSeconds * info.samplerate || info.frames > kMaxAudioSamples) {
    throw IoError(IoErrorKind::kAbsurdCount, name,
                  "declares " + std::to_string(info.frames) + " samples per channel, more than " +
                      std::to_string(static_cast<int>(kMaxAudioSeconds)) + " s or " +
                      std::to_string(kMaxAudioSamples) + " samples");
  }
}

// Decodes block by block and averages the channels.
std::vector<float> DecodeMono(SNDFILE* file, const SF_INFO& info, std::size_t file_bytes, const std::string& name) {
  constexpr sf_count_t kBlockFrames = 4096;
  const auto channels = static_cast<std::size_t>(info.channels);
  std::vector<float> block(static_cast<std::size_t>(kBlockFrames) * channels);
  std::vector<float> mono;
  // Reserved by what the file's size can hold, not what its header claims;
  // compressed audio grows the vector as it decodes.
  mono.reserve(std::min(static_cast<std::size_t>(info.frames), file_bytes));
  while (static_cast<sf_count_t>(mono.size()) < info.frames) {
    const sf_count_t wanted = std::min(kBlockFrames, info.frames - static_cast<sf_count_t>(mono.size()));
    const sf_count_t got = sf_readf_float(file, block.data(), wanted);
    if (got <= 0) break;
    for (sf_count_t f = 0; f < got; ++f) {
      float sum = 0.0f;
      for (std::size_t c = 0; c < channels; ++c) sum += block[static_cast<std::size_t>(f) * channels + c];
      if (!std::isfinite(sum)) {
        throw IoError(IoErrorKind::kNonFinite, name, "sample " + std::to_string(mono.size()) + " is NaN or infinite");
      }
      mono.push_back(sum / static_cast<float>(channels));
    }
  }
  if (static_cast<sf_count_t>(mono.size()) < info.frames) {
    throw IoError(IoErrorKind::kTruncated, name, "the header declares " + std::to_string(info.frames) +
                                                     " samples but only " + std::to_string(mono.size()) +
                                                     " could be decoded");
  }
  return mono;
}

}  // namespace

AudioClip ReadAudioFile(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = ReadInputFile(path, kMaxAudioFileBytes);
  return DecodeAudio(bytes, path.string());
}

AudioClip DecodeAudio(std::span<const std::byte> bytes, const std::string& name) {
  if (bytes.empty()) throw IoError(IoErrorKind::kEmpty, name, "the file is empty");
  MemoryFile memory{bytes};
  SF_VIRTUAL_IO io{&Length, &Seek, &Read, &Write, &Tell};
  SF_INFO info{};
  std::unique_ptr<SNDFILE, SndfileCloser> file(sf_open_virtual(&io, SFM_READ, &info, &memory));
  if (!file) {
    throw IoError(IoErrorKind::kBadMagic, name,
                  std::string("not a readable audio file (libsndfile: ") + sf_strerror(nullptr) + ")");
  }
  CheckHeader(info, name);
  // Float data from integer formats is scaled to [-1, 1]; float files are taken as they are.
  sf_command(file.get(), SFC_SET_NORM_FLOAT, nullptr, SF_TRUE);
  AudioClip clip;
  clip.sample_rate = info.samplerate;
  clip.channels_in_file = info.channels;
  clip.samples = DecodeMono(file.get(), info, bytes.size(), name);
  return clip;
}

}  // namespace facerig
