#include "facerig/runtime/alignment/release_landmark.h"

#include <algorithm>
#include <cmath>

#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig {

std::optional<EnergyRise> SteepestRise(std::span<const float> log_energy, double first, double last) {
  if (log_energy.size() < 2 || !(first <= last)) return std::nullopt;
  // Rise k lies between frames k and k + 1, at position k + 0.5.
  const auto rise = [&](std::ptrdiff_t k) {
    const auto n = static_cast<std::ptrdiff_t>(log_energy.size()) - 2;
    const auto at = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k, 0, n));
    return static_cast<double>(log_energy[at + 1]) - static_cast<double>(log_energy[at]);
  };
  const auto lowest = static_cast<std::ptrdiff_t>(std::max(0.0, std::ceil(first - 0.5)));
  const auto highest = std::min(static_cast<std::ptrdiff_t>(std::floor(last - 0.5)),
                                static_cast<std::ptrdiff_t>(log_energy.size()) - 2);
  if (lowest > highest) return std::nullopt;
  std::ptrdiff_t best = lowest;
  for (std::ptrdiff_t k = lowest + 1; k <= highest; ++k) {
    if (rise(k) > rise(best)) best = k;
  }
  // A parabola through the rises around the steepest places it between frames.
  const double before = rise(best - 1), peak = rise(best), after = rise(best + 1);
  const double curvature = before - 2.0 * peak + after;
  const double offset = curvature < 0.0 ? std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5) : 0.0;
  return EnergyRise{static_cast<double>(best) + 0.5 + offset, peak};
}

namespace {

std::optional<PhonemeVisemes> VisemesOf(const Phoneme& phoneme, std::string_view line_language) {
  return LookupPhonemeVisemes(phoneme.language.empty() ? line_language : phoneme.language.view(), phoneme.symbol.view());
}

}  // namespace

double ReleaseTime(const Phoneme& phoneme, std::string_view line_language) {
  const auto visemes = VisemesOf(phoneme, line_language);
  const bool burst_first = visemes && visemes->has(PhonemeVisemes::kUnvoicedStop);
  return (burst_first ? phoneme.start : phoneme.start + phoneme.duration).count();
}

bool IsBilabial(const Phoneme& phoneme, std::string_view line_language) {
  const auto visemes = VisemesOf(phoneme, line_language);
  return visemes && visemes->count > 0 && visemes->visemes[0] == Viseme::kPP;
}

}  // namespace facerig
