// StreamingAligner's release snap: a /p b m/ the warping path squeezed moves
// onto the recording's own release, as AlignPhonemesToRecording does offline.
#include <algorithm>
#include <array>
#include <cmath>

#include "facerig/runtime/alignment/streaming_alignment.h"
#include "facerig/runtime/alignment/release_landmark.h"

namespace facerig {
namespace {

// Frames the release search copies out of the ring (the reach both ways and a margin).
constexpr std::size_t kReleaseFrames = 64;

}  // namespace

// Each bilabial's release in the reference: the steepest rise of its raw log
// energy (the first feature, before normalisation) near ReleaseTime.
void StreamingAligner::FindReferenceReleases(const SpeechLine& reference) {
  std::vector<float> energy(rows_);
  for (std::size_t f = 0; f < rows_; ++f) energy[f] = reference_[f * dimension_];
  const double hop = cepstra_.hop_samples(), half_window = 0.5 * cepstra_.window_samples();
  const auto frame_at = [&](double seconds) { return (seconds * sample_rate_ - half_window) / hop; };
  releases_.assign(reference.phonemes.size(), {});
  for (std::size_t i = 0; i < reference.phonemes.size(); ++i) {
    const Phoneme& phoneme = reference.phonemes[i];
    if (!IsBilabial(phoneme, reference.language.view())) continue;
    const double expected = ReleaseTime(phoneme, reference.language.view());
    const auto rise = SteepestRise(energy, frame_at(expected - kReferenceReleaseReach),
                                   frame_at(expected + kReferenceReleaseReach));
    if (!rise || rise->rise < kMinReleaseRise) continue;
    const double release = (rise->position * hop + half_window) / sample_rate_;
    const double start = phoneme.start.count(), end = (phoneme.start + phoneme.duration).count();
    releases_[i] = {rise->rise, std::max(0.0, release - start), std::max(0.0, end - release),
                    expected < end};
  }
}

// Recording frames per reference frame along the committed path (1 at first).
double StreamingAligner::PathTempo() const {
  constexpr std::ptrdiff_t kMinRows = 10;
  if (committed_row_ < kMinRows) return 1.0;
  return std::clamp(static_cast<double>(committed_columns_) / static_cast<double>(committed_row_ + 1), 0.5, 2.0);
}

// Bilabial `index`'s start: `start` as warped, or moved onto the recording's
// release when its interval came out squeezed (then snapped_next_start_ holds
// its end); nullopt while its end is not known and may still squeeze it.
std::optional<double> StreamingAligner::SnapToRelease(std::size_t index, double start, bool at_end) {
  const ReferenceRelease& release = releases_[index];
  const double squeezed = kSqueezedFrames * cepstra_.hop_samples() / sample_rate_;
  if (index + 1 == boundary_rows_.size()) return start;
  const std::optional<double> next = BoundaryTime(index + 1, at_end);
  if (!next) {
    const bool may_squeeze = ColumnTime(static_cast<double>(committed_columns_) - 0.5) < start + squeezed;
    return may_squeeze ? std::nullopt : std::optional<double>(start);
  }
  if (*next - start >= squeezed) return start;
  const double warped = release.burst_first ? start : *next;
  if (!at_end && !RecordingHolds(warped + kReleaseReachSeconds)) return std::nullopt;
  const std::optional<double> found = RecordingRelease(warped, kReleaseRiseShare * release.rise);
  if (!found) return start;
  const double tempo = PathTempo();
  snapped_next_start_ = *found + tempo * release.after;
  return *found - tempo * release.before;
}

// The recording's frames reach past `seconds` (and one more for the rise).
bool StreamingAligner::RecordingHolds(double seconds) const {
  const double frame = (seconds * sample_rate_ - 0.5 * cepstra_.window_samples()) / cepstra_.hop_samples();
  return std::ceil(frame) + 2.0 <= static_cast<double>(raw_frames_);
}

// The recording's steepest energy rise within reach of `warped` (seconds), if
// its frames are still in the ring and it rises at least `min_rise`.
std::optional<double> StreamingAligner::RecordingRelease(double warped, double min_rise) const {
  const double hop = cepstra_.hop_samples(), half_window = 0.5 * cepstra_.window_samples();
  const auto frame_at = [&](double seconds) { return (seconds * sample_rate_ - half_window) / hop; };
  const double first = frame_at(warped - kReleaseReachSeconds), last = frame_at(warped + kReleaseReachSeconds);
  const auto lowest = static_cast<std::ptrdiff_t>(std::floor(first)) - 1;
  const auto highest = static_cast<std::ptrdiff_t>(std::ceil(last)) + 1;
  const auto newest = static_cast<std::ptrdiff_t>(raw_frames_) - 1;
  const auto oldest = std::max<std::ptrdiff_t>(0, newest + 1 - static_cast<std::ptrdiff_t>(energy_ring_.size()));
  std::array<float, kReleaseFrames> window{};
  const auto count = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, highest - lowest + 1));
  if (lowest < oldest || highest > newest || count > window.size()) return std::nullopt;
  for (std::size_t k = 0; k < count; ++k) {
    window[k] = energy_ring_[(static_cast<std::size_t>(lowest) + k) % energy_ring_.size()];
  }
  const auto offset = static_cast<double>(lowest);
  const auto rise = SteepestRise(std::span<const float>(window.data(), count), first - offset, last - offset);
  if (!rise || rise->rise < min_rise) return std::nullopt;
  return ((rise->position + offset) * hop + half_window) / sample_rate_;
}

}  // namespace facerig
