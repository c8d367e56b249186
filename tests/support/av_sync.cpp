#include "support/av_sync.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace facerig::test {
namespace {

// Sum of squares of samples[first, last) from a prefix sum.
double Energy(const std::vector<double>& prefix, std::size_t first, std::size_t last) {
  return prefix[last] - prefix[first];
}

std::vector<double> SquarePrefix(std::span<const float> samples) {
  std::vector<double> prefix(samples.size() + 1, 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    prefix[i + 1] = prefix[i] + static_cast<double>(samples[i]) * samples[i];
  }
  return prefix;
}

std::size_t SampleAt(double seconds, int rate, std::size_t size) {
  return static_cast<std::size_t>(std::clamp(std::lround(seconds * rate), 0L, static_cast<long>(size)));
}

}  // namespace

std::vector<double> RmsEnvelope(std::span<const float> samples, int rate, double step, double window) {
  const std::vector<double> prefix = SquarePrefix(samples);
  const double duration = static_cast<double>(samples.size()) / rate;
  std::vector<double> envelope;
  for (double t = 0.0; t < duration; t += step) {
    const std::size_t first = SampleAt(t - 0.5 * window, rate, samples.size());
    const std::size_t last = SampleAt(t + 0.5 * window, rate, samples.size());
    envelope.push_back(last > first ? std::sqrt(Energy(prefix, first, last) / static_cast<double>(last - first)) : 0.0);
  }
  return envelope;
}

std::vector<double> Interpolate(std::span<const double> series, double from_step, double to_step) {
  std::vector<double> out;
  if (series.empty()) return out;
  const double duration = static_cast<double>(series.size()) * from_step;
  for (double t = 0.0; t < duration; t += to_step) {
    const double at = t / from_step;
    const auto i = static_cast<std::size_t>(at);
    const double f = at - static_cast<double>(i);
    out.push_back(i + 1 < series.size() ? (1.0 - f) * series[i] + f * series[i + 1] : series.back());
  }
  return out;
}

namespace {

// Pearson correlation of sound[i] with mouth[i + shift] over the indices both hold.
double CorrelationAtShift(std::span<const double> sound, std::span<const double> mouth, long shift) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  long n = 0;
  for (long i = std::max(0L, -shift); i < static_cast<long>(sound.size()) && i + shift < static_cast<long>(mouth.size());
       ++i) {
    const double a = sound[static_cast<std::size_t>(i)], b = mouth[static_cast<std::size_t>(i + shift)];
    sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
    ++n;
  }
  if (n < 2) return 0.0;
  const auto count = static_cast<double>(n);
  const double cov = sab - sa * sb / count, va = saa - sa * sa / count, vb = sbb - sb * sb / count;
  return va > 0.0 && vb > 0.0 ? cov / std::sqrt(va * vb) : 0.0;
}

}  // namespace

LagPeak PeakLag(std::span<const double> sound, std::span<const double> mouth, double step, double max_lag) {
  LagPeak best{0.0, -2.0};
  const long steps = std::lround(max_lag / step);
  for (long shift = -steps; shift <= steps; ++shift) {
    const double r = CorrelationAtShift(sound, mouth, shift);
    if (r > best.correlation) best = {static_cast<double>(shift) * step, r};
  }
  return best;
}

double QuietestWindow(std::span<const float> samples, int rate, double from, double to, double window) {
  const std::vector<double> prefix = SquarePrefix(samples);
  const auto length = static_cast<std::size_t>(std::lround(window * rate));
  double best_start = from, best_energy = -1.0;
  for (double t = from; t <= to + 1e-9; t += 0.001) {
    const std::size_t first = SampleAt(t, rate, samples.size());
    if (first + length > samples.size()) break;
    const double energy = Energy(prefix, first, first + length);
    if (best_energy < 0.0 || energy < best_energy) best_energy = energy, best_start = t;
  }
  return best_start;
}

}  // namespace facerig::test
