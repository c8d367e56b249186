// Audio-visual sync measured from outputs only: a per-frame mouth series
// (from rendered pixels) against the audio's RMS envelope (from the WAV),
// cross-correlated over lags, and the quietest window where a lip closure
// should silence the recording. Shared by tests/demo and facerig-bench.
#pragma once

#include <span>
#include <vector>

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

}  // namespace facerig::test
