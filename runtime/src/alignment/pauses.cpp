#include "facerig/runtime/alignment/pauses.h"

#include <cmath>

#include "audio/percentile.h"

namespace facerig {

std::vector<bool> QuietFrames(std::span<const float> log_energy, const PauseParams& params) {
  std::vector<bool> quiet(log_energy.size(), false);
  if (log_energy.empty()) return quiet;
  std::vector<float> sorted(log_energy.begin(), log_energy.end());
  const double low = detail::PercentileInPlace(sorted, 0.05), high = detail::PercentileInPlace(sorted, 0.95);
  if (!(high - low >= params.min_range)) return quiet;
  const double threshold = low + params.quiet_share * (high - low);
  for (std::size_t f = 0; f < log_energy.size(); ++f) quiet[f] = log_energy[f] < threshold;
  return quiet;
}

std::vector<Pause> FindPauses(std::span<const float> log_energy, double hop_seconds, const PauseParams& params) {
  std::vector<Pause> pauses;
  if (log_energy.empty() || !(hop_seconds > 0.0)) return pauses;
  const std::vector<bool> quiet = QuietFrames(log_energy, params);
  const auto frames_of = [&](double seconds) { return static_cast<std::size_t>(std::ceil(seconds / hop_seconds - 1e-9)); };
  const std::size_t edge = frames_of(params.min_edge_seconds), inner = frames_of(params.min_inner_seconds);
  const std::size_t n = log_energy.size();
  for (std::size_t f = 0; f < n;) {
    if (!quiet[f]) {
      ++f;
      continue;
    }
    std::size_t end = f;
    while (end < n && quiet[end]) ++end;
    const bool at_edge = f == 0 || end == n;
    if (end - f >= (at_edge ? edge : inner)) pauses.push_back({f, end - 1});
    f = end;
  }
  return pauses;
}

std::vector<bool> PauseMask(std::span<const Pause> pauses, std::size_t frames) {
  std::vector<bool> mask(frames, false);
  for (const Pause& pause : pauses) {
    for (std::size_t f = pause.first; f <= pause.last && f < frames; ++f) mask[f] = true;
  }
  return mask;
}

}  // namespace facerig
