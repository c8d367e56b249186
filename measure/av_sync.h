// Audio-visual sync measured from outputs only: a per-frame mouth series
// (from rendered pixels) against the audio's RMS envelope (from the WAV),
// cross-correlated over lags, and the quietest window where a lip closure
// should silence the recording. Shared by tests/demo and facerig-bench.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig::test {

// RMS of `samples` (rate Hz) in a window of `window` s centred every `step` s from 0.
std::vector<double> RmsEnvelope(std::span<const float> samples, int rate, double step, double window);

// A series sampled every `from_step` s, linearly interpolated every `to_step` s
// (the last value held past the end).
std::vector<double> Interpolate(std::span<const double> series, double from_step, double to_step);

struct LagPeak {
  double lag_seconds = 0.0;  // > 0: the mouth follows the sound
  double correlation = 0.0;  // Pearson correlation at that lag
};

// The lag in [-max_lag, max_lag] (steps of `step` s) where mouth(t + lag)
// correlates best with sound(t); both series sampled every `step` s from 0.
LagPeak PeakLag(std::span<const double> sound, std::span<const double> mouth, double step, double max_lag);

// Start (s) of the lowest-energy `window` s of `samples` whose start lies in
// [from, to] s, searched in 1 ms steps; `from` when the range holds none.
double QuietestWindow(std::span<const float> samples, int rate, double from, double to, double window);

// A box of pixels [x0, x1) x [y0, y1).
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// 8-bit interleaved pixels (row-major, row 0 at the top) of one frame.
struct FramePixels {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> values;
};

// Mean absolute difference (0..255) of the first three channels over the box.
double BoxDifference(const FramePixels& frame, const FramePixels& first, const PixelBox& box);

// The mouth box from the pixels alone (a still head: only the face moves):
// in the frames' lower half (below the eyes, so blinks stay out), the
// bounding box of the pixels whose largest change from frame 0 is at least
// a quarter of the largest there. Empty (x1 <= x0) when nothing changes.
PixelBox ChangingLowerBox(std::span<const FramePixels> frames);

// The per-frame mouth series: BoxDifference from frame 0.
std::vector<double> MouthSeries(std::span<const FramePixels> frames, const PixelBox& box);

// The lag of a per-frame mouth series (at `fps`) against the RMS envelope of
// `samples` (in windows of one frame interval), in 1 ms steps within +-150 ms.
// Both series start at the same instant (frame 0 = sample 0).
LagPeak MouthLag(std::span<const double> mouth, double fps, std::span<const float> samples, int rate);

struct BilabialClosure {
  std::string symbol;
  double lips_least_open = 0.0;              // s: the frame with the least opening in the search window
  double lips_from = 0.0, lips_to = 0.0;     // s: frames around it at most 15% of the widest opening
  double acoustic_from = 0.0, acoustic_to = 0.0;  // s: the quietest 30 ms in the window
  bool overlaps() const { return lips_from < acoustic_to && acoustic_from < lips_to; }
};

// Each /p b m/ of `phonemes` (times in the recording; the WAV and frames hold
// them `offset` s later): searched between the preceding vowel's middle and
// the next vowel's onset (from the track) in the mouth series and the audio.
std::vector<BilabialClosure> MeasureBilabialClosures(std::span<const double> mouth, double fps,
                                                     std::span<const float> samples, int rate,
                                                     std::span<const Phoneme> phonemes, double offset);

}  // namespace facerig::test
