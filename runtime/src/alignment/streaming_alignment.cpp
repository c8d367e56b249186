#include "facerig/runtime/alignment/streaming_alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "facerig/runtime/alignment/dtw_align.h"
#include "facerig/runtime/alignment/pauses.h"
#include "audio/deltas.h"
#include "audio/feature_statistics.h"
#include "audio/percentile.h"

namespace facerig {
namespace {

using detail::DeltasOf;
using detail::kDeltaReach;
// The onset moves back to where its energy began to rise, at most this many
// frames: a quiet voiced closure (a /b/ or /m/ first) belongs to the speech.
constexpr std::size_t kMaxOnsetWalkBack = 8;
// Raw frames kept: the deltas' reach both ways, and the onset's walk back.
constexpr std::size_t kHistory = 2 * kDeltaReach + 1 + kMaxOnsetWalkBack;
// A boundary may lie up to this many frames before the column committed when it is emitted.
constexpr std::size_t kEmitSlack = 2;
// Frames before the speech onset (in both) where the warping starts.
constexpr std::size_t kOnsetMargin = kDeltaReach;
// Speech: louder than this share of the way from the reference's quiet
// frames (5th percentile) to its loud ones (95th), above the recording's floor.
constexpr double kOnsetShare = 0.35;
// Quiet, for pauses: below this share of that range above the floor (as in pauses.h).
constexpr double kQuietShare = 0.25;
// A stream's first frame is speech when it is at most this much quieter
// (natural log of energy, 10 dB) than the reference's first frame, itself
// speech: the reference's range, which reaches down to its digital silence,
// would let room noise pass for a quiet first consonant (/D/ of "The").
constexpr double kSpeechAtStartTolerance = 2.3;
// Latency the release snap (streaming_release.cpp) may add: waiting for a
// bilabial's end and moving its start earlier.
constexpr double kReleaseLatency = 0.050;
// Recording frames kept for the release search, beyond the look-ahead.
constexpr std::size_t kEnergyMargin = 32;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Consecutive vertical steps (reference frames on one recording frame) the
// path may take: a longer climb skips speech the recording has not reached.
constexpr std::uint8_t kMaxVerticalRun = 10;
// A pause starting this many rows before the reference's own pause crosses it.
constexpr std::size_t kPauseReach = 3;
// A diagonal step costs this many times its cell (a horizontal or vertical
// one, once): below the symmetric 2, the path keeps moving through the
// reference instead of waiting on a row and catching up late, which a path
// committed after a short look-ahead cannot undo.
constexpr double kDiagonalWeight = 1.35;
enum Step : std::uint8_t { kStart, kHorizontal, kDiagonal, kVertical };

// The reference's raw features (cepstra and deltas), frame-major.
std::vector<float> ReferenceFeatures(const SpeechLine& reference, FrameCepstra& cepstra, std::size_t dimension) {
  const std::vector<float> audio = PcmToFloat(reference.audio);
  const auto hop = static_cast<std::size_t>(cepstra.hop_samples()), window = static_cast<std::size_t>(cepstra.window_samples());
  const std::size_t frames = audio.size() <= window ? 1 : 1 + (audio.size() - window + hop - 1) / hop;
  const std::size_t n = static_cast<std::size_t>(cepstra.cepstra());
  std::vector<float> values(frames * dimension), padded(window);
  for (std::size_t f = 0; f < frames; ++f) {
    const std::size_t start = f * hop;
    for (std::size_t i = 0; i < window; ++i) padded[i] = start + i < audio.size() ? audio[start + i] : 0.0f;
    cepstra.Compute(padded, start > 0 ? audio[start - 1] : 0.0f, std::span<float>(values).subspan(f * dimension, n));
  }
  for (std::size_t f = 0; f < frames; ++f) {
    const auto at = [&](std::ptrdiff_t k) {
      const auto g = std::clamp<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(f) + k, 0, static_cast<std::ptrdiff_t>(frames) - 1);
      return values.data() + static_cast<std::size_t>(g) * dimension;
    };
    DeltasOf(n, at, values.data() + f * dimension + n);
  }
  return values;
}

}  // namespace

StreamingAligner::StreamingAligner(const SpeechLine& reference, const StreamingAlignmentParams& params)
    : cepstra_(reference.sample_rate > 0 ? reference.sample_rate : 1, params.features),
      params_(params),
      sample_rate_(reference.sample_rate) {
  if (reference.audio.empty() || reference.sample_rate <= 0) {
    throw AlignmentError("the reference line has no audio to align with");
  }
  if (reference.phonemes.empty()) throw AlignmentError("the reference line has no phonemes");
  const double hop = static_cast<double>(cepstra_.hop_samples()) / sample_rate_;
  const double half_window = 0.5 * cepstra_.window_samples() / sample_rate_;
  const double frames_ahead =
      std::floor((params.look_ahead_seconds - half_window) / hop) - static_cast<double>(kDeltaReach + kEmitSlack);
  if (!(frames_ahead >= 1.0) || !(params.band_radius_seconds > 0.0) || !(params.prior_frames >= 0.0)) {
    throw std::invalid_argument("StreamingAligner: look-ahead shorter than the window, or a bad band or prior");
  }
  lag_ = static_cast<std::size_t>(frames_ahead);
  dimension_ = 2 * static_cast<std::size_t>(cepstra_.cepstra());
  reference_ = ReferenceFeatures(reference, cepstra_, dimension_);
  rows_ = reference_.size() / dimension_;
  radius_ = static_cast<std::size_t>(std::ceil(params.band_radius_seconds / hop));
  pause_frames_ = params.pauses ? static_cast<std::size_t>(std::max(1.0, std::ceil(params.pause_seconds / hop - 1e-9))) : 0;
  // A pause is warped again from its first frame, which must not be committed yet.
  if (pause_frames_ > lag_) throw std::invalid_argument("StreamingAligner: pause_seconds longer than the look-ahead");
  FindReferenceOnset();
  FindReferencePauses(reference);
  FindReferenceReleases(reference);
  NormalizeReference(params.prior_frames);
  // The warping starts a few frames before the reference's speech; earlier
  // boundaries keep their distance to it.
  onset_margin_ = std::min(onset_row_, kOnsetMargin);
  const std::size_t start_row = onset_row_ - onset_margin_;
  reference_.erase(reference_.begin(), reference_.begin() + static_cast<std::ptrdiff_t>(start_row * dimension_));
  reference_pause_.erase(reference_pause_.begin(), reference_pause_.begin() + static_cast<std::ptrdiff_t>(start_row));
  rows_ -= start_row;
  width_ = std::min(2 * radius_ + 1, rows_);
  for (const Phoneme& phoneme : reference.phonemes) {
    boundary_rows_.push_back((phoneme.start.count() * sample_rate_ - 0.5 * cepstra_.window_samples()) /
                                 cepstra_.hop_samples() - static_cast<double>(start_row));
  }
  raw_history_.assign(kHistory * dimension_, 0.0f);
  energy_ring_.assign(std::max(lag_ + kHistory + kEnergyMargin, pause_frames_ + kHistory), 0.0f);
  if (pause_frames_ > 0) {
    saved_lows_.assign(pause_frames_ + 1, 0);
    saved_best_.assign(pause_frames_ + 1, 0);
    saved_costs_.assign(saved_lows_.size() * width_, kInfinity);
    saved_runs_.assign(saved_lows_.size() * width_, 0);
  }
  frame_.resize(dimension_);
  column_features_.resize(dimension_);
  previous_cost_.assign(width_, kInfinity);
  cost_.assign(width_, kInfinity);
  vertical_run_.assign(width_, 0);
  steps_.assign((lag_ + 1) * width_, kStart);
  step_lows_.assign(lag_ + 1, 0);
  path_low_.reserve(lag_ + 2);
  path_high_.reserve(lag_ + 2);
  first_column_.assign(rows_, 0);
  last_column_.assign(rows_, 0);
  emitted_.reserve(boundary_rows_.size());
}

void StreamingAligner::FindReferenceOnset() {
  std::vector<float> energy(rows_);
  for (std::size_t f = 0; f < rows_; ++f) energy[f] = reference_[f * dimension_];
  std::vector<float> sorted = energy;
  const double low = detail::PercentileInPlace(sorted, 0.05), high = detail::PercentileInPlace(sorted, 0.95);
  onset_rise_ = kOnsetShare * (high - low);
  quiet_rise_ = kQuietShare * (high - low);
  floor_cap_ = 0.5 * (low + high);
  onset_row_ = 0;
  while (onset_row_ + 1 < rows_ && energy[onset_row_] < low + onset_rise_) ++onset_row_;
  if (onset_row_ + 1 == rows_) onset_row_ = 0;  // no speech stands out
  if (onset_row_ == 0) speech_at_start_ = energy[0] - std::min(onset_rise_, kSpeechAtStartTolerance);
  for (std::size_t walked = 0; walked < kMaxOnsetWalkBack && onset_row_ > 0; ++walked) {
    if (!(energy[onset_row_ - 1] < energy[onset_row_])) break;
    --onset_row_;  // back to where the rise began, as the recording's onset
  }
}

// The reference's rows on which the recording's pauses are crossed for free:
// its own pauses (as offline, where crossing on a stop closure moved the
// stop past the recording's pause) and its pause phonemes.
void StreamingAligner::FindReferencePauses(const SpeechLine& reference) {
  std::vector<float> energy(rows_);
  for (std::size_t f = 0; f < rows_; ++f) energy[f] = reference_[f * dimension_];
  PauseParams edges_any_length;
  edges_any_length.quiet_share = kQuietShare;
  edges_any_length.min_edge_seconds = 0.0;
  const double hop = static_cast<double>(cepstra_.hop_samples()) / sample_rate_;
  const std::vector<bool> pause_rows = PauseMask(FindPauses(energy, hop, edges_any_length), rows_);
  reference_pause_.assign(pause_rows.begin(), pause_rows.end());
  const double half_window = 0.5 * cepstra_.window_samples() / sample_rate_;
  pause_phonemes_.clear();
  for (const Phoneme& phoneme : reference.phonemes) {
    pause_phonemes_.push_back(IsPausePhoneme(phoneme, reference.language.view()) ? 1 : 0);
    if (!pause_phonemes_.back()) continue;
    const auto row_at = [&](double seconds) { return std::max(0.0, std::ceil((seconds - half_window) / hop)); };
    const auto first = static_cast<std::size_t>(row_at(phoneme.start.count()));
    const auto end = std::min(rows_, static_cast<std::size_t>(row_at((phoneme.start + phoneme.duration).count())));
    for (std::size_t f = first; f < end; ++f) reference_pause_[f] = 1;
  }
}

// The reference's features to zero mean and unit variance; its statistics,
// weighted as `prior_frames` frames, seed the recording's running ones.
void StreamingAligner::NormalizeReference(double prior_frames) {
  sums_.assign(dimension_, 0.0);
  squares_.assign(dimension_, 0.0);
  for (std::size_t d = 0; d < dimension_; ++d) {
    const detail::DimensionStatistics statistics = detail::StatisticsOf(reference_, dimension_, d);
    detail::Normalize(reference_, dimension_, d, statistics);
    sums_[d] = statistics.mean * prior_frames;
    squares_[d] = (statistics.variance + statistics.mean * statistics.mean) * prior_frames;
  }
  count_ = prior_frames;
}

double StreamingAligner::FrameEnd() const {
  return (static_cast<double>(raw_frames_ - 1) * cepstra_.hop_samples() + cepstra_.window_samples()) / sample_rate_;
}

double StreamingAligner::look_ahead_seconds() const {
  return (static_cast<double>(lag_ + kDeltaReach + kEmitSlack) * cepstra_.hop_samples() + 0.5 * cepstra_.window_samples()) /
             sample_rate_ +
         kReleaseLatency;
}

std::span<const StreamedBoundary> StreamingAligner::Push(std::span<const float> samples) {
  emitted_.clear();
  samples_.insert(samples_.end(), samples.begin(), samples.end());
  pushed_samples_ += samples.size();
  pushed_seconds_ = static_cast<double>(pushed_samples_) / sample_rate_;
  const auto hop = static_cast<std::size_t>(cepstra_.hop_samples()), window = static_cast<std::size_t>(cepstra_.window_samples());
  std::size_t offset = 0;
  for (; offset + window <= samples_.size(); offset += hop) {
    cepstra_.Compute(std::span<const float>(samples_).subspan(offset, window), previous_sample_,
                     std::span<float>(frame_).first(static_cast<std::size_t>(cepstra_.cepstra())));
    previous_sample_ = samples_[offset + hop - 1];
    ProcessFrame();
  }
  samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(offset));
  return emitted_;
}

void StreamingAligner::ProcessFrame() {
  const auto n = static_cast<std::size_t>(cepstra_.cepstra());
  std::copy_n(frame_.begin(), n, raw_history_.begin() + static_cast<std::ptrdiff_t>((raw_frames_ % kHistory) * dimension_));
  energy_ring_[raw_frames_ % energy_ring_.size()] = frame_[0];
  ++raw_frames_;
  // Leading silence is not warped: a silence's features drift with the
  // running normalisation and pull the band off. Speech starts above the
  // floor so far, capped for a stream that starts loud.
  floor_ = std::min(floor_, static_cast<double>(frame_[0]));
  // A stream that starts as loud as a reference that starts with speech
  // starts with speech too: no rise above a floor will mark it.
  const bool speech_at_start = raw_frames_ == 1 && frame_[0] > speech_at_start_;
  if (!started_ && (speech_at_start || frame_[0] > std::min(floor_, floor_cap_) + onset_rise_)) {
    started_ = true;
    const std::size_t onset = RisingFrom(raw_frames_ - 1);
    next_frame_ = column_offset_ = onset > onset_margin_ ? onset - onset_margin_ : 0;
    EmitReady(FrameEnd(), false);  // the boundaries before the onset keep their distance to it
  }
  while (started_ && next_frame_ + kDeltaReach < raw_frames_) AddColumn(next_frame_++);
}

// The first frame of the energy rise that reaches recording frame `frame`.
std::size_t StreamingAligner::RisingFrom(std::size_t frame) const {
  const std::size_t ring = energy_ring_.size();
  for (std::size_t walked = 0; walked < kMaxOnsetWalkBack && frame > 0 && raw_frames_ - frame < ring; ++walked) {
    if (!(energy_ring_[(frame - 1) % ring] < energy_ring_[frame % ring])) break;
    --frame;
  }
  return frame;
}

// Recording frame `column` (its raw cepstra in the history) as a normalised
// feature column, warped and, once the look-ahead passed, committed.
void StreamingAligner::AddColumn(std::size_t frame) {
  const auto n = static_cast<std::size_t>(cepstra_.cepstra());
  const auto at = [&](std::ptrdiff_t k) {
    const auto last = static_cast<std::ptrdiff_t>(raw_frames_) - 1;
    const auto g = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(frame) + k, 0, last));
    return raw_history_.data() + (g % kHistory) * dimension_;
  };
  std::copy_n(at(0), n, column_features_.begin());
  DeltasOf(n, at, column_features_.data() + n);
  count_ += 1.0;
  for (std::size_t d = 0; d < dimension_; ++d) {
    const double v = column_features_[d];
    sums_[d] += v;
    squares_[d] += v * v;
    const double mean = sums_[d] / count_, variance = std::max(0.0, squares_[d] / count_ - mean * mean);
    column_features_[d] = variance > 1e-12 ? static_cast<float>((v - mean) / std::sqrt(variance)) : 0.0f;
  }
  const bool pause = columns_ > 0 && InPause(frame);
  if (pause && !in_pause_) {
    pause_first_column_ = columns_;
    RewindIntoPause(frame);
    pause_end_column_ = std::numeric_limits<std::size_t>::max();
  } else if (!pause && in_pause_) {
    pause_end_column_ = columns_;
  }
  in_pause_ = pause;
  if (pause) {
    FillPauseColumn();
  } else {
    FillColumn(column_features_);
  }
  SaveColumn();
  quiet_run_ = pause_frames_ > 0 && Quiet(frame) ? quiet_run_ + 1 : 0;
  if (columns_ > lag_) {
    // While the newest frames may begin a pause, the path is the one that
    // led to the frame before them: warped as speech, silence pulls it ahead.
    const std::size_t commit = columns_ - 1 - lag_;
    const bool may_begin_pause = !in_pause_ && quiet_run_ > 0 && quiet_run_ <= pause_frames_ && quiet_run_ < columns_;
    const std::size_t from = may_begin_pause ? columns_ - 1 - quiet_run_ : columns_ - 1;
    Backtrack(from, may_begin_pause ? saved_best_[from % saved_best_.size()] : BestRow(), from - commit + 1);
    CommitColumn(commit, path_low_.back(), path_high_.back());
    EmitReady(FrameEnd(), false);
  }
}

void StreamingAligner::FillColumn(std::span<const float> x) {
  const std::size_t j = columns_;
  if (j > 0) {
    const auto centre = static_cast<std::ptrdiff_t>(BestRow()) + 1;
    std::swap(previous_cost_, cost_);
    previous_low_ = low_;
    const auto wanted = centre - static_cast<std::ptrdiff_t>(radius_);
    low_ = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(
        wanted, static_cast<std::ptrdiff_t>(previous_low_),
        static_cast<std::ptrdiff_t>(std::min(previous_low_ + 2, rows_ - width_))));
  }
  const std::size_t slot = j % (lag_ + 1);
  step_lows_[slot] = low_;
  const auto previous = [&](std::size_t row) {
    return row >= previous_low_ && row < previous_low_ + width_ ? previous_cost_[row - previous_low_] : kInfinity;
  };
  for (std::size_t c = 0; c < width_; ++c) {
    const std::size_t row = low_ + c;
    double d = 0.0;
    for (std::size_t k = 0; k < dimension_; ++k) {
      const double diff = static_cast<double>(reference_[row * dimension_ + k]) - x[k];
      d += diff * diff;
    }
    d = std::sqrt(d);
    double best = kInfinity;
    std::uint8_t step = kStart;
    if (j == 0 && row == 0) best = d;
    const bool may_climb = c > 0 && vertical_run_[c - 1] < kMaxVerticalRun;
    const double candidates[3] = {j > 0 ? previous(row) + d : kInfinity,
                                  j > 0 && row > 0 ? previous(row - 1) + kDiagonalWeight * d : kInfinity,
                                  may_climb ? cost_[c - 1] + d : kInfinity};
    for (std::uint8_t s = 0; s < 3; ++s) {
      if (candidates[s] < best) {
        best = candidates[s];
        step = static_cast<std::uint8_t>(kHorizontal + s);
      }
    }
    cost_[c] = best;
    steps_[slot * width_ + c] = step;
    vertical_run_[c] = step == kVertical ? static_cast<std::uint8_t>(vertical_run_[c - 1] + 1) : 0;
  }
  ++columns_;
}

// Recording frame `frame` (still in the energy ring) is quiet.
bool StreamingAligner::Quiet(std::size_t frame) const {
  return energy_ring_[frame % energy_ring_.size()] < std::min(floor_, floor_cap_) + quiet_rise_;
}

// Recording frame `frame` ends pause_frames_ quiet frames (0: pauses are off).
bool StreamingAligner::InPause(std::size_t frame) const {
  const std::size_t ring = energy_ring_.size();
  if (pause_frames_ == 0 || frame + 1 < pause_frames_ || raw_frames_ - (frame + 1 - pause_frames_) > ring) return false;
  for (std::size_t f = frame + 1 - pause_frames_; f <= frame; ++f) {
    if (!Quiet(f)) return false;
  }
  return true;
}

// A column of a pause: every path waits on its row at its own mean cost per
// step (the rows' ranking in BestRow holds, so the pause neither pulls the
// path ahead nor holds it back), except that the path's row moves on at no
// cost, one row per column, through the reference's pause that follows it.
// The band stays where it is.
void StreamingAligner::FillPauseColumn() {
  std::swap(previous_cost_, cost_);
  previous_low_ = low_;
  const std::size_t slot = columns_ % (lag_ + 1);
  step_lows_[slot] = low_;
  const auto column = static_cast<double>(columns_);
  for (std::size_t c = 0; c < width_; ++c) {
    const double held = previous_cost_[c] * (1.0 + 1.0 / (static_cast<double>(low_ + c) + column + 1.0));
    const std::size_t row = low_ + c;
    const bool crossing = row > pause_row_ && row <= pause_top_row_ && c > 0;
    const bool moves = crossing && previous_cost_[c - 1] < held;
    cost_[c] = moves ? previous_cost_[c - 1] : held;
    steps_[slot * width_ + c] = moves ? kDiagonal : kHorizontal;
    vertical_run_[c] = 0;
  }
  ++columns_;
}

// The rows a pause starting now crosses: from the path's row (the best) on
// through the reference's pause rows that follow it within kPauseReach rows.
void StreamingAligner::StartPause() {
  pause_row_ = pause_top_row_ = BestRow();
  // The phoneme the path is in: one it has barely begun (less than half of
  // its rows) is spoken after the pause, and starts at its end.
  const double middle = static_cast<double>(pause_row_) + 0.5;
  const auto next = std::upper_bound(boundary_rows_.begin(), boundary_rows_.end(), middle);
  pause_phoneme_ = kNoPause;
  if (next != boundary_rows_.begin() && next != boundary_rows_.end() && middle - *(next - 1) < 0.5 * (*next - *(next - 1))) {
    pause_phoneme_ = static_cast<std::size_t>(next - boundary_rows_.begin()) - 1;
  }
  const std::size_t top = low_ + width_ - 1;
  std::size_t row = pause_row_;
  while (row < top && row < pause_row_ + kPauseReach && !reference_pause_[row + 1]) ++row;
  if (row == top || !reference_pause_[row + 1]) return;
  while (row < top && reference_pause_[row + 1]) ++row;
  pause_top_row_ = row;
}

// The newest column's costs, band and vertical runs, for RewindIntoPause.
void StreamingAligner::SaveColumn() {
  if (pause_frames_ == 0) return;
  const std::size_t slot = (columns_ - 1) % saved_lows_.size();
  std::copy(cost_.begin(), cost_.end(), saved_costs_.begin() + static_cast<std::ptrdiff_t>(slot * width_));
  std::copy(vertical_run_.begin(), vertical_run_.end(), saved_runs_.begin() + static_cast<std::ptrdiff_t>(slot * width_));
  saved_lows_[slot] = low_;
  saved_best_[slot] = BestRow();
}

// Recording frame `frame` makes its quiet run a pause: the run's columns
// not committed yet (all but those before the warping's first) are warped
// again as a pause's, from the state before its first.
void StreamingAligner::RewindIntoPause(std::size_t frame) {
  const std::size_t run_frame = frame + 1 - pause_frames_;
  const std::size_t run_column = run_frame > column_offset_ ? run_frame - column_offset_ : 0;
  const std::size_t first = std::max<std::size_t>({run_column, committed_columns_, 1});
  const std::size_t end = columns_;
  if (first >= end) {
    StartPause();
    return;
  }
  const std::size_t slot = (first - 1) % saved_lows_.size();
  std::copy_n(saved_costs_.begin() + static_cast<std::ptrdiff_t>(slot * width_), width_, cost_.begin());
  std::copy_n(saved_runs_.begin() + static_cast<std::ptrdiff_t>(slot * width_), width_, vertical_run_.begin());
  low_ = saved_lows_[slot];
  pause_first_column_ = columns_ = first;
  StartPause();
  while (columns_ < end) {
    FillPauseColumn();
    SaveColumn();
  }
}

std::size_t StreamingAligner::BestRow() const {
  const double column = static_cast<double>(columns_ - 1);
  std::size_t best = low_;
  double best_cost = kInfinity;
  for (std::size_t c = 0; c < width_; ++c) {
    const double normalised = cost_[c] / (static_cast<double>(low_ + c) + column + 2.0);
    if (normalised < best_cost) {
      best_cost = normalised;
      best = low_ + c;
    }
  }
  return best;
}

// The path from (from_row, from_column) back over `columns` columns (all
// within the look-ahead): its lowest and highest row in each, newest first.
void StreamingAligner::Backtrack(std::size_t from_column, std::size_t from_row, std::size_t columns) {
  path_low_.clear();
  path_high_.clear();
  std::size_t column = from_column, row = from_row, high = row;
  while (true) {
    const std::size_t slot = column % (lag_ + 1);
    const std::uint8_t step = steps_[slot * width_ + (row - step_lows_[slot])];
    if (step == kVertical) {
      --row;
      continue;
    }
    path_low_.push_back(row);
    path_high_.push_back(high);
    if (step == kStart || path_low_.size() == columns) return;
    --column;
    if (step == kDiagonal) --row;
    high = row;
  }
}

void StreamingAligner::CommitColumn(std::size_t column, std::size_t lowest_row, std::size_t highest_row) {
  const auto high = static_cast<std::ptrdiff_t>(highest_row);
  if (high <= committed_row_) {
    last_column_[static_cast<std::size_t>(committed_row_)] = column;  // the path waits on its row
  } else {
    const auto first = std::max<std::ptrdiff_t>(std::max<std::ptrdiff_t>(committed_row_, 0),
                                                std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(lowest_row), committed_row_ + 1));
    for (auto row = first; row <= high; ++row) {
      if (row > committed_row_) first_column_[static_cast<std::size_t>(row)] = column;
      last_column_[static_cast<std::size_t>(row)] = column;
    }
    committed_row_ = high;
  }
  committed_columns_ = column + 1;
}

// Phoneme `index`'s start on the recording once the committed path decides it.
std::optional<double> StreamingAligner::BoundaryTime(std::size_t index, bool at_end) const {
  const auto boundary = [&](std::size_t k) {
    if (k == 0) return -0.5;
    if (k == rows_) return static_cast<double>(last_column_[rows_ - 1]) + 0.5;
    return 0.5 * static_cast<double>(last_column_[k - 1] + first_column_[k]);
  };
  const double rows = static_cast<double>(rows_);
  const double row = boundary_rows_[index];
  double column = row;
  if (row >= rows - 0.5) {
    if (!at_end) return std::nullopt;
    column = boundary(rows_) + (row - (rows - 0.5));
  } else if (row >= -0.5) {
    // Inside reference frame k, advancing at most one recording frame: a
    // frame the recording holds longer is final once the path stayed on it
    // that long, without waiting for the path to leave it.
    const auto k = static_cast<std::size_t>(std::floor(row + 0.5));
    if (static_cast<std::ptrdiff_t>(k) > committed_row_) return std::nullopt;
    const bool next_known = static_cast<std::ptrdiff_t>(k + 1) <= committed_row_ || at_end;
    const double committed_edge = static_cast<double>(committed_columns_) - 0.5;
    if (!next_known && committed_edge < boundary(k) + 1.0) return std::nullopt;
    const double span = next_known ? std::min(boundary(k + 1) - boundary(k), 1.0) : 1.0;
    column = boundary(k) + (row + 0.5 - static_cast<double>(k)) * span;
  }
  return ColumnTime(column);
}

double StreamingAligner::ColumnTime(double column) const {
  return ((column + static_cast<double>(column_offset_)) * cepstra_.hop_samples() + 0.5 * cepstra_.window_samples()) /
         sample_rate_;
}

void StreamingAligner::EmitReady(double decided_at, bool at_end) {
  for (; next_phoneme_ < boundary_rows_.size(); ++next_phoneme_) {
    const std::optional<double> time = BoundaryTime(next_phoneme_, at_end);
    if (!time) return;
    double start = *time;
    if (snapped_next_start_ >= 0.0) {
      start = snapped_next_start_;  // the end of a bilabial moved onto its release
      snapped_next_start_ = -1.0;
    } else if (releases_[next_phoneme_].rise > 0.0) {
      const std::optional<double> snapped = SnapToRelease(next_phoneme_, start, at_end);
      if (!snapped) return;
      start = *snapped;
    }
    if (!pause_phonemes_[next_phoneme_]) {
      const std::optional<double> outside = OutOfPause(start, at_end, next_phoneme_ == pause_phoneme_);
      if (!outside) return;
      start = *outside;
    }
    start = std::max(start, decided_at - look_ahead_seconds());
    last_start_ = std::clamp(start, last_start_, std::max(last_start_, pushed_seconds_));
    emitted_.push_back({next_phoneme_, Seconds(last_start_), decided_at});
  }
}

// A phoneme (not a pause phoneme) starting at `start` seconds, kept out of
// the latest pause as offline: one that starts inside (or `after`, spoken
// after it) starts at its end; nullopt while that end is not known.
std::optional<double> StreamingAligner::OutOfPause(double start, bool at_end, bool after) const {
  if (pause_first_column_ == kNoPause) return start;
  if (!after && start < ColumnTime(static_cast<double>(pause_first_column_) - 0.5)) return start;
  if (pause_end_column_ == kNoPause) return at_end ? std::optional<double>(start) : std::nullopt;
  return std::max(start, ColumnTime(static_cast<double>(pause_end_column_) - 0.5));
}

std::span<const StreamedBoundary> StreamingAligner::Finish() {
  emitted_.clear();
  if (raw_frames_ == 0 && !samples_.empty()) {
    samples_.resize(static_cast<std::size_t>(cepstra_.window_samples()), 0.0f);
    cepstra_.Compute(samples_, 0.0f, std::span<float>(frame_).first(static_cast<std::size_t>(cepstra_.cepstra())));
    ProcessFrame();
  }
  samples_.clear();
  if (!started_ && raw_frames_ > 0) {
    started_ = true;  // no speech: the last frame stands for all
    next_frame_ = column_offset_ = raw_frames_ - 1;
  }
  while (next_frame_ < raw_frames_) AddColumn(next_frame_++);
  if (columns_ > committed_columns_) {
    const bool end_in_band = low_ + width_ == rows_ && std::isfinite(cost_[width_ - 1]);
    Backtrack(columns_ - 1, end_in_band ? rows_ - 1 : BestRow(), columns_ - committed_columns_);
    for (std::size_t i = path_low_.size(); i-- > 0;) CommitColumn(committed_columns_, path_low_[i], path_high_[i]);
  }
  const std::size_t last = columns_ > 0 ? columns_ - 1 : 0;
  for (auto row = committed_row_ + 1; row < static_cast<std::ptrdiff_t>(rows_); ++row) {
    first_column_[static_cast<std::size_t>(row)] = last_column_[static_cast<std::size_t>(row)] = last;
  }
  committed_row_ = static_cast<std::ptrdiff_t>(rows_) - 1;
  EmitReady(pushed_seconds_, true);
  return emitted_;
}

}  // namespace facerig
