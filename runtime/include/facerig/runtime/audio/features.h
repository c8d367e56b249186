// Per-frame spectral features of speech audio (MFCC with deltas), the input
// of the transcript-to-recording alignment (phoneme_alignment.h).
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace facerig {

struct AudioFeatureParams {
  double hop_seconds = 0.010;     // one frame every hop (rounded to whole samples)
  double window_seconds = 0.025;  // Hann window per frame
  int mel_bands = 26;
  // c1..c5 and log energy in place of c0: the higher cepstra hold more of
  // the speaker (vocal tract length) than of the phoneme, and cost accuracy
  // when two voices are compared.
  int cepstra = 6;
  double low_hz = 80.0;           // mel filter bank range; the top is capped at Nyquist
  double high_hz = 7600.0;
  bool deltas = true;             // append each coefficient's slope over +-2 frames
};

// Frame f covers samples [f * hop_samples, f * hop_samples + window_samples);
// its time is its centre.
struct AudioFeatures {
  int sample_rate = 0;
  int hop_samples = 0;
  int window_samples = 0;
  int dimension = 0;
  std::vector<float> values;      // frame-major, frame_count() x dimension
  std::vector<float> log_energy;  // natural log of each frame's mean power (before normalisation)

  std::size_t frame_count() const { return dimension > 0 ? values.size() / static_cast<std::size_t>(dimension) : 0; }
  std::span<const float> frame(std::size_t index) const {
    return std::span<const float>(values).subspan(index * static_cast<std::size_t>(dimension),
                                                  static_cast<std::size_t>(dimension));
  }
  double hop_seconds() const { return static_cast<double>(hop_samples) / sample_rate; }
  // Time of frame `index`'s centre, in seconds (fractional indices allowed).
  double FrameTime(double index) const {
    return (index * hop_samples + 0.5 * window_samples) / sample_rate;
  }
};

// MFCC (+ deltas) of mono `samples` (any scale) at `sample_rate` Hz, each
// dimension normalised to zero mean and unit variance over the utterance so
// that two voices or microphones compare. Audio shorter than one window gives
// one frame of the zero-padded audio; empty audio gives no frames.
// \throw std::invalid_argument for a sample rate <= 0 or unusable params.
AudioFeatures ComputeAudioFeatures(std::span<const float> samples, int sample_rate,
                                   const AudioFeatureParams& params = {});

// The un-normalised cepstra of one frame at a time (log energy, c1..), as
// ComputeAudioFeatures computes them but with fixed energy floors instead of
// ones relative to the loudest frame: for audio that arrives in pieces.
// Compute does not allocate.
class FrameCepstra {
 public:
  // \throw std::invalid_argument as ComputeAudioFeatures.
  FrameCepstra(int sample_rate, const AudioFeatureParams& params);
  int hop_samples() const { return hop_; }
  int window_samples() const { return static_cast<int>(hann_.size()); }
  int cepstra() const { return cepstra_; }
  // `window`: window_samples() samples; `previous`: the sample before them
  // (0 at the start); `out`: cepstra() values.
  void Compute(std::span<const float> window, float previous, std::span<float> out);

 private:
  struct Filter {
    std::size_t first_bin = 0;
    std::vector<float> weights;
  };
  int hop_ = 0, cepstra_ = 0;
  std::vector<float> hann_, spectrum_, log_mel_;
  std::vector<Filter> bank_;
  std::vector<float> cosines_;  // cepstra x bands
  std::vector<std::complex<float>> buffer_;
};

// 16-bit PCM to floats in [-1, 1).
std::vector<float> PcmToFloat(std::span<const std::int16_t> samples);

}  // namespace facerig
