#include "facerig/runtime/alignment/phoneme_alignment.h"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>
#include <vector>

#include "facerig/runtime/alignment/release_landmark.h"
#include "audio/percentile.h"

namespace facerig {
namespace {

// Frames louder than this share of the way from the quiet end of the
// energies (5th percentile) to the loud end (95th) count as speech.
constexpr double kSpeechEnergyShare = 0.35;

// First and last frame of speech (the whole range when no frame stands out).
std::pair<double, double> SpeechEndpoints(const AudioFeatures& features) {
  const std::vector<float>& energy = features.log_energy;
  std::vector<float> sorted = energy;
  const double low = detail::PercentileInPlace(sorted, 0.05), high = detail::PercentileInPlace(sorted, 0.95);
  const double threshold = low + kSpeechEnergyShare * (high - low);
  std::size_t first = 0, last = energy.size() - 1;
  while (first < last && energy[first] < threshold) ++first;
  while (last > first && energy[last] < threshold) --last;
  if (high - low < 1e-3) return {0.0, static_cast<double>(energy.size() - 1)};
  return {static_cast<double>(first), static_cast<double>(last)};
}

// The band's centre: straight lines through the corners and both speech endpoints.
std::vector<double> GuideLine(const AudioFeatures& reference, const AudioFeatures& recording) {
  const auto [ref_start, ref_end] = SpeechEndpoints(reference);
  const auto [rec_start, rec_end] = SpeechEndpoints(recording);
  const double n = static_cast<double>(reference.frame_count() - 1), m = static_cast<double>(recording.frame_count() - 1);
  const double xs[4] = {0.0, ref_start, ref_end, n}, ys[4] = {0.0, rec_start, rec_end, m};
  std::vector<double> centre(reference.frame_count());
  for (std::size_t i = 0; i < centre.size(); ++i) {
    const double x = static_cast<double>(i);
    std::size_t s = 0;
    while (s < 2 && x > xs[s + 1]) ++s;
    const double span = xs[s + 1] - xs[s];
    centre[i] = span > 0.0 ? ys[s] + (x - xs[s]) / span * (ys[s + 1] - ys[s]) : ys[s + 1];
  }
  return centre;
}

std::size_t BandRadiusFrames(const AudioFeatures& recording, const PhonemeAlignmentParams& params) {
  const double duration = static_cast<double>(recording.frame_count()) * recording.hop_seconds();
  const double seconds = std::min(params.max_band_radius_seconds,
                                  std::max(params.band_radius_seconds, params.band_radius_fraction * duration));
  return static_cast<std::size_t>(std::ceil(std::max(0.0, seconds) / recording.hop_seconds()));
}

void CheckInputs(const SpeechLine& reference, std::span<const float> recording) {
  if (reference.audio.empty() || reference.sample_rate <= 0) {
    throw AlignmentError("the reference line has no audio to align with");
  }
  if (reference.phonemes.empty()) throw AlignmentError("the reference line has no phonemes");
  if (recording.empty()) throw AlignmentError("the recording is empty");
}

// Fractional frame index of a time (the inverse of FrameTime).
double FrameAt(const AudioFeatures& features, double seconds) {
  return (seconds * features.sample_rate - 0.5 * features.window_samples) / features.hop_samples;
}

// Recording seconds per reference second around [start, end] along the path.
double LocalTempo(double start, double end, const DtwPath& path, const AudioFeatures& ref, const AudioFeatures& rec) {
  constexpr double kContext = 0.100;
  const double from = std::max(0.0, start - kContext), to = end + kContext;
  const double mapped = MapReferenceTime(to, path, ref, rec) - MapReferenceTime(from, path, ref, rec);
  return std::clamp(mapped / (to - from), 0.5, 2.0);
}

// Each squeezed /p b m/ onto the recording's own release: the reference's
// release (its steepest energy rise near the phoneme's ReleaseTime) is warped
// across, the recording's steepest rise within reach of it taken instead when
// it is a clear one, and the phoneme placed around it with the reference's
// timing at the local tempo. Its neighbours give or take the time.
void SnapBilabialsToReleases(const SpeechLine& reference, const DtwPath& path, const AudioFeatures& ref,
                             const AudioFeatures& rec, double recording_end, std::vector<Phoneme>& phonemes) {
  for (std::size_t i = 0; i < phonemes.size(); ++i) {
    const Phoneme& source = reference.phonemes[i];
    if (!IsBilabial(source, reference.language.view())) continue;
    const double ref_start = source.start.count(), ref_end = (source.start + source.duration).count();
    if (phonemes[i].duration.count() >= kSqueezedFrames * rec.hop_seconds()) continue;
    const double expected = ReleaseTime(source, reference.language.view());
    const auto ref_rise = SteepestRise(ref.log_energy, FrameAt(ref, expected - kReferenceReleaseReach),
                                       FrameAt(ref, expected + kReferenceReleaseReach));
    if (!ref_rise || ref_rise->rise < kMinReleaseRise) continue;
    const double ref_release = ref.FrameTime(ref_rise->position);
    const double warped = MapReferenceTime(ref_release, path, ref, rec);
    const auto rec_rise = SteepestRise(rec.log_energy, FrameAt(rec, warped - kReleaseReachSeconds),
                                       FrameAt(rec, warped + kReleaseReachSeconds));
    if (!rec_rise || rec_rise->rise < kReleaseRiseShare * ref_rise->rise) continue;
    const double release = rec.FrameTime(rec_rise->position);
    const double tempo = LocalTempo(ref_start, ref_end, path, ref, rec);
    const double lowest = i > 0 ? phonemes[i - 1].start.count() : 0.0;
    const double highest = i + 2 < phonemes.size() ? phonemes[i + 2].start.count() : recording_end;
    // A release outside the neighbours' room (a transcript that does not fit
    // the recording) would turn the clamps below around.
    if (release < lowest || release > highest) continue;
    const double start = std::clamp(release - tempo * (ref_release - ref_start), lowest, release);
    const double end = std::clamp(release + tempo * (ref_end - ref_release), std::max(start, release), highest);
    if (i > 0) phonemes[i - 1].duration = Seconds(start - lowest);
    if (i + 1 < phonemes.size()) {
      Phoneme& next = phonemes[i + 1];
      const double next_end = std::max(end, (next.start + next.duration).count());
      next.start = Seconds(end);
      next.duration = Seconds(next_end - end);
    }
    phonemes[i].start = Seconds(start);
    phonemes[i].duration = Seconds(end - start);
  }
}

struct Interval {
  double start = 0.0, end = 0.0;
};

// The recording's pauses in seconds: frame edges, the first and last
// extended to the recording's ends.
std::vector<Interval> PauseIntervals(const std::vector<Pause>& pauses, const AudioFeatures& rec, double recording_end) {
  std::vector<Interval> intervals;
  const double half_hop = 0.5 * rec.hop_seconds();
  for (const Pause& pause : pauses) {
    const double start = pause.first == 0 ? 0.0 : rec.FrameTime(static_cast<double>(pause.first)) - half_hop;
    const double end = pause.last + 1 >= rec.frame_count() ? recording_end
                                                           : rec.FrameTime(static_cast<double>(pause.last)) + half_hop;
    intervals.push_back({std::max(0.0, start), std::min(recording_end, end)});
  }
  return intervals;
}

// No phoneme but a pause lies in a pause: one that starts inside starts at
// its end, one that runs into it ends at its start. Starts stay in order.
void KeepOutOfPauses(const std::vector<Interval>& pauses, std::string_view language, std::vector<Phoneme>& phonemes) {
  double previous_start = 0.0;
  for (Phoneme& phoneme : phonemes) {
    double start = phoneme.start.count(), end = (phoneme.start + phoneme.duration).count();
    if (!IsPausePhoneme(phoneme, language)) {
      for (const Interval& pause : pauses) {
        if (start >= pause.end || end <= pause.start) continue;
        if (start >= pause.start) {
          start = pause.end;
          end = std::max(end, start);
        } else {
          end = pause.start;
        }
      }
    }
    start = std::max(start, previous_start);
    phoneme.start = Seconds(start);
    phoneme.duration = Seconds(std::max(end, start) - start);
    previous_start = start;
  }
}

// The fixed cost of a pause frame on any reference row: the expected distance
// of two unrelated frames of normalised features (unit variance per
// dimension), so that consuming the reference's speech there is no bargain.
double PauseCost(const AudioFeatures& features) { return std::sqrt(2.0 * static_cast<double>(features.dimension)); }

// The reference's rows on which a pause of the recording is crossed for
// free: its own silence before and after its speech, and pauses inside it as
// long as the recording's (a stop closure is quiet too, but crossing there
// would move the stop's release past the recording's pause).
std::vector<bool> ReferencePauseRows(const AudioFeatures& ref, const PauseParams& params) {
  PauseParams edges_any_length = params;
  edges_any_length.min_edge_seconds = 0.0;
  return PauseMask(FindPauses(ref.log_energy, ref.hop_seconds(), edges_any_length), ref.frame_count());
}

// The features (and the pause flags) with their frames in reverse order.
AudioFeatures Reversed(const AudioFeatures& features) {
  AudioFeatures reversed = features;
  const std::size_t n = features.frame_count(), d = static_cast<std::size_t>(features.dimension);
  for (std::size_t f = 0; f < n; ++f) {
    std::copy_n(features.values.begin() + static_cast<std::ptrdiff_t>((n - 1 - f) * d), d,
                reversed.values.begin() + static_cast<std::ptrdiff_t>(f * d));
  }
  std::reverse(reversed.log_energy.begin(), reversed.log_energy.end());
  return reversed;
}

// The confidence of `path` (see PhonemeAlignment::confidence): the reference
// warped onto the reversed recording is the baseline of an unrelated match.
double MatchConfidence(const AudioFeatures& ref, const AudioFeatures& rec, const DtwPath& path, std::size_t radius,
                       const DtwPauseColumns* pauses, std::size_t max_cells) {
  const AudioFeatures reversed = Reversed(rec);
  DtwPauseColumns reversed_pauses;
  if (pauses) reversed_pauses = {std::vector<bool>(pauses->quiet.rbegin(), pauses->quiet.rend()), pauses->quiet_rows, pauses->cost};
  const DtwBand band = MakeDtwBand(GuideLine(ref, reversed), reversed.frame_count(), radius);
  const DtwPath baseline = AlignFeatureSequences(ref, reversed, band, max_cells, pauses ? &reversed_pauses : nullptr);
  return baseline.mean_distance > 0.0 ? 1.0 - path.mean_distance / baseline.mean_distance : 0.0;
}

}  // namespace

double MapReferenceTime(double reference_seconds, const DtwPath& path, const AudioFeatures& reference,
                        const AudioFeatures& recording) {
  const std::size_t n = path.first_column.size();
  // Rows and columns as positions on a frame-centre axis; row i spans [i - 0.5, i + 0.5].
  const double row = (reference_seconds * reference.sample_rate - 0.5 * reference.window_samples) /
                     reference.hop_samples;
  // Column at the boundary between rows k - 1 and k (k in 0..n).
  const auto boundary = [&](std::size_t k) {
    if (k == 0) return -0.5;
    if (k == n) return static_cast<double>(path.last_column[n - 1]) + 0.5;
    return 0.5 * static_cast<double>(path.last_column[k - 1] + path.first_column[k]);
  };
  double column = 0.0;
  if (row < -0.5) {
    column = row;  // before the first frame: the two timelines run at the same pace
  } else if (row >= static_cast<double>(n) - 0.5) {
    column = boundary(n) + (row - (static_cast<double>(n) - 0.5));
  } else {
    const auto k = static_cast<std::size_t>(std::floor(row + 0.5));
    const double share = row + 0.5 - static_cast<double>(k);
    column = boundary(k) + share * (boundary(k + 1) - boundary(k));
  }
  return std::max(0.0, recording.FrameTime(column));
}

PhonemeAlignment AlignPhonemesToRecording(const SpeechLine& reference, std::span<const float> recording,
                                          const PhonemeAlignmentParams& params) {
  CheckInputs(reference, recording);
  const std::vector<float> reference_audio = PcmToFloat(reference.audio);
  const AudioFeatures ref = ComputeAudioFeatures(reference_audio, reference.sample_rate, params.features);
  const AudioFeatures rec = ComputeAudioFeatures(recording, reference.sample_rate, params.features);
  const std::size_t radius = BandRadiusFrames(rec, params);
  const DtwBand band = MakeDtwBand(GuideLine(ref, rec), rec.frame_count(), radius);
  const std::vector<Pause> pauses =
      params.pauses ? FindPauses(rec.log_energy, rec.hop_seconds(), params.pause_params) : std::vector<Pause>{};
  const DtwPauseColumns pause_columns{PauseMask(pauses, rec.frame_count()), ReferencePauseRows(ref, params.pause_params),
                                      PauseCost(rec)};
  const DtwPauseColumns* crossed = pauses.empty() ? nullptr : &pause_columns;
  const DtwPath path = AlignFeatureSequences(ref, rec, band, params.max_cells, crossed);

  const double recording_end = static_cast<double>(recording.size()) / reference.sample_rate;
  PhonemeAlignment result;
  result.cost = path.cost;
  result.pauses = pauses.size();
  result.confidence = MatchConfidence(ref, rec, path, radius, crossed, params.max_cells);
  const auto [ref_start, ref_end] = SpeechEndpoints(ref);
  const auto [rec_start, rec_end] = SpeechEndpoints(rec);
  result.tempo = ref_end > ref_start ? (rec_end - rec_start + 1.0) / (ref_end - ref_start + 1.0) : 1.0;
  result.line.text = reference.text;
  result.line.language = reference.language;
  result.line.phonemes = reference.phonemes;
  double previous_start = 0.0;
  for (Phoneme& phoneme : result.line.phonemes) {
    const double start = std::clamp(MapReferenceTime(phoneme.start.count(), path, ref, rec), previous_start, recording_end);
    const double end = phoneme.duration.count() > 0.0
                           ? MapReferenceTime((phoneme.start + phoneme.duration).count(), path, ref, rec)
                           : start;
    phoneme.start = Seconds(start);
    phoneme.duration = Seconds(std::clamp(end, start, recording_end) - start);
    previous_start = start;
  }
  SnapBilabialsToReleases(reference, path, ref, rec, recording_end, result.line.phonemes);
  KeepOutOfPauses(PauseIntervals(pauses, rec, recording_end), reference.language.view(), result.line.phonemes);
  return result;
}

}  // namespace facerig
