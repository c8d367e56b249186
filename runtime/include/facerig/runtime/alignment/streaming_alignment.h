// Lip-sync for speech that arrives in chunks (a cloud TTS stream) with its
// transcript: the online form of phoneme_alignment.h. The reference (the
// transcript synthesised in full up front, with exact phoneme boundaries)
// gives the rows of a dynamic time warping, the recording's frames arrive as
// columns. Each column is filled inside a band that follows the best cell of
// the previous column; after each column the path is traced back from the
// best cell over the look-ahead, and the column the look-ahead left behind is
// committed: the boundaries it passes are emitted, final.
//
// Latency: a boundary is emitted once the audio reaches its emitted time plus
// look_ahead_seconds() (decided_at in StreamedBoundary says when exactly): the
// params' look-ahead and up to 50 ms more for a /p b m/ the path squeezed,
// which waits for its end and moves onto the recording's release (the
// steepest energy rise within 40 ms, as in AlignPhonemesToRecording).
// Memory: the reference's features and per-row path columns (fixed at
// construction), the band's costs and (look-ahead x band) back-pointers.
// Push allocates nothing once its buffers reached the largest chunk's size.
// Features are normalised with running statistics of the recording seeded
// with the reference's, as the whole recording is not known. The warping
// starts at the recording's speech onset (a frame louder than its quiet floor
// by a share of the reference's loudness range; the floor is capped for a
// stream that starts with speech, which assumes levels within ~10 dB of the
// reference's; a first frame as loud as the reference's, when that starts
// with speech, is the onset), in both moved back to where its energy rise began
// (a quiet voiced closure first, as in "Be ...", is speech); boundaries before
// the reference's onset keep their distance to it and are emitted at the
// onset. Diagonal steps cost less than a horizontal plus a vertical one, so
// the path follows the reference's tempo rather than stalling on a row and
// catching up later than the look-ahead can correct.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "facerig/runtime/audio/features.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

struct StreamingAlignmentParams {
  AudioFeatureParams features;  // deltas are always used
  // A boundary is final once the audio reaches its time plus this (at least
  // the window, two frames for the deltas and one frame of path); a squeezed
  // /p b m/ up to 50 ms later.
  double look_ahead_seconds = 0.25;
  // Half-width of the band of reference frames searched per recording frame.
  double band_radius_seconds = 0.5;
  // Weight, in frames, of the reference's feature statistics in the running
  // normalisation of the recording's.
  double prior_frames = 100.0;
  // Pauses: once the recording has been quiet (below a quarter of the
  // reference's loudness range above the recording's floor) for
  // pause_seconds, its quiet run, from its first frame on, is a pause: the
  // path waits on its row (or crosses the reference's own pause or pause
  // phoneme that follows it, one row per frame), and a phoneme that starts
  // inside the pause, or that the path had barely begun (less than half of
  // its rows), starts at the pause's end, as offline. Until the run is that
  // long it may be a stop closure and is warped like speech, but the path
  // committed meanwhile is the one that led to its first frame; the run is
  // then warped again as a pause, which the look-ahead allows (pause_seconds
  // must fit in it). false: every frame after the onset is warped like
  // speech (a pause's silence is matched to the next words).
  bool pauses = true;
  double pause_seconds = 0.15;
};

struct StreamedBoundary {
  std::size_t phoneme = 0;  // index in the reference's phonemes
  Seconds start{};          // its start on the recording (non-decreasing over the stream)
  double decided_at = 0.0;  // audio time (seconds of recording) that made it final
};

class StreamingAligner {
 public:
  // `reference`: audio and exactly timed phonemes of the transcript. The
  // recording must have the reference's sample rate.
  // \throw AlignmentError (dtw_align.h) for a reference without audio or
  // phonemes; std::invalid_argument for bad params.
  explicit StreamingAligner(const SpeechLine& reference, const StreamingAlignmentParams& params = {});

  // Appends mono samples; returns the boundaries they made final (valid until
  // the next call).
  std::span<const StreamedBoundary> Push(std::span<const float> samples);
  // The end of the recording: the remaining boundaries (all of them).
  std::span<const StreamedBoundary> Finish();

  // The latency bound: emitted start + this >= decided_at for every boundary.
  double look_ahead_seconds() const;
  std::size_t phoneme_count() const { return boundary_rows_.size(); }

 private:
  void FindReferenceOnset();
  void FindReferencePauses(const SpeechLine& reference);
  void NormalizeReference(double prior_frames);
  double FrameEnd() const;  // the audio time the newest frame needed
  void ProcessFrame();
  std::size_t RisingFrom(std::size_t frame) const;
  void AddColumn(std::size_t frame);
  void FillColumn(std::span<const float> x);
  void FillPauseColumn();
  void StartPause();
  void SaveColumn();
  void RewindIntoPause(std::size_t frame);
  bool Quiet(std::size_t frame) const;
  bool InPause(std::size_t frame) const;
  std::size_t BestRow() const;
  void Backtrack(std::size_t from_column, std::size_t from_row, std::size_t columns);
  void CommitColumn(std::size_t column, std::size_t lowest_row, std::size_t highest_row);
  void EmitReady(double decided_at, bool at_end);
  std::optional<double> BoundaryTime(std::size_t index, bool at_end) const;
  std::optional<double> OutOfPause(double start, bool at_end, bool after) const;
  double ColumnTime(double column) const;
  // The release snap of bilabials (streaming_release.cpp).
  void FindReferenceReleases(const SpeechLine& reference);
  std::optional<double> SnapToRelease(std::size_t index, double start, bool at_end);
  std::optional<double> RecordingRelease(double warped, double min_rise) const;
  bool RecordingHolds(double seconds) const;
  double PathTempo() const;

  // A /p b m/'s release in the reference (rise 0: none, or not a bilabial).
  struct ReferenceRelease {
    double rise = 0.0;                           // its log-energy rise
    double before = 0.0, after = 0.0;            // seconds from the phoneme's start to it, from it to the end
    bool burst_first = false;                    // released at the start (unvoiced stop) rather than the end
  };

  FrameCepstra cepstra_;
  StreamingAlignmentParams params_;
  int sample_rate_ = 0;
  std::size_t dimension_ = 0, rows_ = 0, width_ = 0, lag_ = 0, radius_ = 0;
  std::vector<float> reference_;                    // rows_ x dimension_, normalised
  std::vector<std::uint8_t> reference_pause_;       // per row: in one of the reference's pauses or pause phonemes
  std::vector<std::uint8_t> pause_phonemes_;        // per phoneme: a pause phoneme (may lie in a pause)
  std::vector<double> boundary_rows_;               // each phoneme's start on the reference's frame axis
  std::vector<double> sums_, squares_;              // running statistics of the recording's raw features
  double count_ = 0.0;
  std::vector<float> samples_;                      // audio not yet framed (and the sample before it)
  float previous_sample_ = 0.0f;
  std::vector<float> raw_history_;                  // the last frames' cepstra, for the deltas and the onset
  std::size_t raw_frames_ = 0, columns_ = 0;
  // Warping starts at the recording's speech onset: column 0 is recording
  // frame column_offset_, row 0 the reference's frame onset_row_ - margin.
  std::size_t onset_row_ = 0, column_offset_ = 0, next_frame_ = 0;
  // The frames before the onset where the warping starts, the same in both:
  // kOnsetMargin, or fewer when the reference's speech starts sooner.
  std::size_t onset_margin_ = 0;
  bool started_ = false;
  double onset_rise_ = 0.0, floor_cap_ = 0.0, quiet_rise_ = 0.0;
  std::size_t pause_frames_ = 0;
  bool in_pause_ = false;                           // the newest column is a pause's
  static constexpr std::size_t kNoPause = std::numeric_limits<std::size_t>::max();
  // The latest pause's first column and the first after it (kNoPause: none yet, or not ended).
  std::size_t pause_first_column_ = kNoPause, pause_end_column_ = kNoPause;
  // The row the path waits on in the latest pause, and the last one it may cross to.
  std::size_t pause_row_ = 0, pause_top_row_ = 0;
  std::size_t pause_phoneme_ = kNoPause;            // the phoneme the path had barely begun when it began
  // The last pause_frames_ + 1 columns' costs, band and vertical runs, by
  // column in a ring: a pause found late is warped again from its start.
  std::vector<double> saved_costs_;
  std::vector<std::uint8_t> saved_runs_;
  std::vector<std::size_t> saved_lows_, saved_best_;
  std::size_t quiet_run_ = 0;                       // quiet frames up to the newest column
  // A first recording frame louder than this is speech (infinite: the reference starts quiet).
  double speech_at_start_ = std::numeric_limits<double>::infinity();
  double floor_ = std::numeric_limits<double>::infinity();
  std::vector<float> frame_, column_features_;
  std::vector<double> previous_cost_, cost_;
  std::vector<std::uint8_t> vertical_run_;          // vertical steps ending in each cell of the column
  std::size_t previous_low_ = 0, low_ = 0;
  std::vector<std::uint8_t> steps_;                 // (lag_ + 1) x width_ back-pointers, a ring by column
  std::vector<std::size_t> step_lows_;              // each ring column's first row
  std::vector<std::size_t> path_low_, path_high_;   // Backtrack's rows per column, newest first
  std::vector<std::size_t> first_column_, last_column_;
  std::size_t committed_columns_ = 0;
  std::ptrdiff_t committed_row_ = -1;
  std::size_t next_phoneme_ = 0;
  double last_start_ = 0.0, pushed_seconds_ = 0.0;
  std::size_t pushed_samples_ = 0;
  std::vector<StreamedBoundary> emitted_;
  std::vector<ReferenceRelease> releases_;         // per phoneme
  std::vector<float> energy_ring_;                  // the recording's last frames' log energy, by raw frame
  double snapped_next_start_ = -1.0;                // the next start, set by a bilabial moved onto its release
};

}  // namespace facerig
