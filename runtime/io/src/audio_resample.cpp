#include <samplerate.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "facerig/runtime/io/audio_file.h"

namespace facerig {

std::vector<float> ResampleAudio(std::span<const float> samples, int from_rate, int to_rate) {
  const auto valid = [](int rate) { return rate > 0 && rate <= kMaxAudioSampleRate; };
  if (!valid(from_rate) || !valid(to_rate)) {
    throw std::invalid_argument("ResampleAudio: sample rates " + std::to_string(from_rate) + " -> " +
                                std::to_string(to_rate) + " Hz out of range");
  }
  if (from_rate == to_rate || samples.empty()) return std::vector<float>(samples.begin(), samples.end());
  const double ratio = static_cast<double>(to_rate) / from_rate;
  std::vector<float> out(static_cast<std::size_t>(std::ceil(static_cast<double>(samples.size()) * ratio)) + 1);
  SRC_DATA data{};
  data.data_in = samples.data();
  data.input_frames = static_cast<long>(samples.size());
  data.data_out = out.data();
  data.output_frames = static_cast<long>(out.size());
  data.src_ratio = ratio;
  const int error = src_simple(&data, SRC_SINC_MEDIUM_QUALITY, 1);
  if (error != 0) throw std::runtime_error(std::string("libsamplerate: ") + src_strerror(error));
  out.resize(static_cast<std::size_t>(data.output_frames_gen));
  return out;
}

}  // namespace facerig
