#include "facerig/runtime/alignment/pauses.h"

#include <algorithm>
#include <cmath>

#include "audio/percentile.h"
#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig {

namespace {

struct EnergyRange {
  double low = 0.0, high = 0.0;  // 5th and 95th percentiles
};

EnergyRange RangeOf(std::span<const float> log_energy) {
  std::vector<float> sorted(log_energy.begin(), log_energy.end());
  return {detail::PercentileInPlace(sorted, 0.05), detail::PercentileInPlace(sorted, 0.95)};
}

// Frame f's energy averaged with its neighbours: the rise toward speech, not
// the noise's wiggles.
double Smoothed(std::span<const float> e, std::size_t f) {
  const std::size_t first = f > 0 ? f - 1 : f, last = f + 1 < e.size() ? f + 1 : f;
  double sum = 0.0;
  for (std::size_t k = first; k <= last; ++k) sum += e[k];
  return sum / static_cast<double>(last - first + 1);
}

// Whether quiet[first, last) holds a run of at least `frames` quiet frames.
bool HasQuietRun(const std::vector<bool>& quiet, std::size_t first, std::size_t last, std::size_t frames) {
  std::size_t run = 0;
  for (std::size_t f = first; f < last; ++f) {
    run = quiet[f] ? run + 1 : 0;
    if (run >= frames) return true;
  }
  return false;
}

// Where the recording starts (ends) with silence, marks quiet everything
// before the energy's rise toward the first loud frame (after its fall from
// the last): see PauseParams::loud_share.
void QuietUpToSpeech(std::span<const float> e, EnergyRange range, const PauseParams& params, std::size_t edge_frames,
                     std::vector<bool>& quiet) {
  const std::size_t n = e.size();
  const auto [low, high] = range;
  const double loud = std::max(low + params.loud_share * (high - low), high - params.loud_depth);
  std::size_t first = 0;
  while (first < n && e[first] <= loud) ++first;
  if (first == n) return;
  std::size_t last = n - 1;
  while (e[last] <= loud) --last;
  if (HasQuietRun(quiet, 0, first, edge_frames)) {
    while (first > 0 && Smoothed(e, first - 1) < Smoothed(e, first)) --first;
    std::fill(quiet.begin(), quiet.begin() + static_cast<std::ptrdiff_t>(first), true);
  }
  if (HasQuietRun(quiet, last + 1, n, edge_frames)) {
    while (last + 1 < n && Smoothed(e, last + 1) < Smoothed(e, last)) ++last;
    std::fill(quiet.begin() + static_cast<std::ptrdiff_t>(last + 1), quiet.end(), true);
  }
}

// QuietFrames with the energies' range already known.
std::vector<bool> QuietFramesIn(std::span<const float> log_energy, EnergyRange range, const PauseParams& params) {
  std::vector<bool> quiet(log_energy.size(), false);
  const auto [low, high] = range;
  if (!(high - low >= params.min_range)) return quiet;
  const double threshold = low + params.quiet_share * (high - low);
  for (std::size_t f = 0; f < log_energy.size(); ++f) quiet[f] = log_energy[f] < threshold;
  return quiet;
}

}  // namespace

std::vector<bool> QuietFrames(std::span<const float> log_energy, const PauseParams& params) {
  if (log_energy.empty()) return {};
  return QuietFramesIn(log_energy, RangeOf(log_energy), params);
}

std::vector<Pause> FindPauses(std::span<const float> log_energy, double hop_seconds, const PauseParams& params) {
  std::vector<Pause> pauses;
  if (log_energy.empty() || !(hop_seconds > 0.0)) return pauses;
  const EnergyRange range = RangeOf(log_energy);
  std::vector<bool> quiet = QuietFramesIn(log_energy, range, params);
  const auto frames_of = [&](double seconds) { return static_cast<std::size_t>(std::ceil(seconds / hop_seconds - 1e-9)); };
  const std::size_t edge = frames_of(params.min_edge_seconds), inner = frames_of(params.min_inner_seconds);
  QuietUpToSpeech(log_energy, range, params, std::max<std::size_t>(edge, 1), quiet);
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

bool IsPausePhoneme(const Phoneme& phoneme, std::string_view line_language) {
  const auto visemes = LookupPhonemeVisemes(phoneme.language.empty() ? line_language : phoneme.language.view(),
                                            phoneme.symbol.view());
  return visemes && visemes->count > 0 && visemes->visemes[0] == Viseme::kSil;
}

}  // namespace facerig
