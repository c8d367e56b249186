// Float samples to 16-bit PCM: apart from audio_file.cpp so that builds
// without libsndfile (the WebAssembly module, hosts/web) have it too.
#include <algorithm>
#include <cmath>

#include "facerig/runtime/io/audio_file.h"

namespace facerig {

std::vector<std::int16_t> FloatToPcm(std::span<const float> samples) {
  std::vector<std::int16_t> out(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    out[i] = static_cast<std::int16_t>(std::lround(std::clamp(samples[i], -1.0f, 32767.0f / 32768.0f) * 32768.0f));
  }
  return out;
}

}  // namespace facerig
