#include "facerig/runtime/alignment/pauses.h"

#include <cmath>

#include "audio/percentile.h"

namespace facerig {

std::vector<Pause> FindPauses(std::span<const float> log_energy, double hop_seconds, const PauseParams& params) {
  std::vector<Pause> pauses;
  if (log_energy.empty() || !(hop_seconds > 0.0)) return pauses;
  std::vector<float> sorted(log_energy.begin(), log_energy.end());
  const double low = detail::PercentileInPlace(sorted, 0.05), high = detail::PercentileInPlace(sorted, 0.95);
  if (!(high - low >= params.min_range)) return pauses;
  const double threshold = low + params.quiet_share * (high - low);
  const auto frames_of = [&](double seconds) { return static_cast<std::size_t>(std::ceil(seconds / hop_seconds - 1e-9)); };
  const std::size_t edge = frames_of(params.min_edge_seconds), inner = frames_of(params.min_inner_seconds);
  const std::size_t n = log_energy.size();
  for (std::size_t f = 0; f < n;) {
    if (!(log_energy[f] < threshold)) {
      ++f;
      continue;
    }
    std::size_t end = f;
    while (end < n && log_energy[end] < threshold) ++end;
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
