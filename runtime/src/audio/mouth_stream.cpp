#include "facerig/runtime/audio/mouth_stream.h"

#include <algorithm>
#include <cmath>

#include "audio/mouth_frame_analyzer.h"
#include "audio/mouth_segments.h"

namespace facerig {
namespace {

// Longest phoneme emitted: a long segment comes out in pieces of this length.
constexpr double kPieceSeconds = 0.100;

}  // namespace

struct RoughMouthStream::State {
  State(int sample_rate, const AudioMouthParams& params);

  template <typename Sample>
  void Push(std::span<const Sample> samples, std::vector<Phoneme>& out);
  void Finish(std::vector<Phoneme>& out);
  void AnalyzeFrames(bool flush);
  void SmoothFrames(bool flush);
  void Classify(const MouthFrameFeatures& frame);
  void CommitFrames(bool flush, std::vector<Phoneme>& out);
  MouthShape FrontSymbol();
  void EmitPiece(double end, std::vector<Phoneme>& out);
  void Reset();

  AudioMouthParams params;
  int sample_rate = 0;
  std::size_t hop = 0;  // samples
  double hop_seconds = 0.0;
  std::size_t median_half = 0;   // frames
  std::size_t min_frames = 1;    // shortest segment
  std::size_t delay_frames = 1;  // look-ahead of the segment decisions
  std::size_t piece_frames = 1;
  MouthFrameAnalyzer analyzer;
  std::vector<float> frame;

  // Audio not yet analysed; samples[0] is sample samples_start of the line.
  std::vector<float> samples;
  std::size_t samples_start = 0;
  std::size_t samples_total = 0;

  // Unsmoothed features of frames raw_start..; counts of frames analysed and smoothed.
  std::vector<MouthFrameFeatures> raw;
  std::size_t raw_start = 0;
  std::size_t analyzed = 0;
  std::size_t smoothed = 0;

  bool have_levels = false;
  float floor_db = 0.0f;
  float loud_db = 0.0f;
  bool voiced = false;

  // Classified frames not yet committed; shapes[0] is frame `committed`.
  std::vector<MouthShape> shapes;
  std::vector<MouthRun> runs;
  std::size_t committed = 0;
  MouthShape run_shape = MouthShape::kRest;   // merged class of the last committed frame
  MouthShape run_symbol = MouthShape::kRest;  // what its run is written as
  std::size_t run_count = 0;                  // committed frames of that run
  // Committed frames not yet emitted.
  MouthShape piece_symbol = MouthShape::kRest;
  std::size_t piece_count = 0;
  double emitted_end = 0.0;
};

RoughMouthStream::State::State(int rate, const AudioMouthParams& p)
    : params(p),
      sample_rate(rate),
      hop(MouthHopSamples(rate, p.analysis)),
      analyzer(std::clamp(rate, kMouthMinSampleRate, kMouthMaxSampleRate),
               hop > 0 ? MouthWindowSamples(rate, p.analysis) : 2) {
  if (hop == 0) return;
  hop_seconds = double(hop) / rate;
  median_half = static_cast<std::size_t>(MouthMedianFrames(p) / 2);
  min_frames = MouthFramesFor(p.min_segment, hop_seconds);
  // Enough to see a whole closure and to merge a short run with both neighbours.
  delay_frames = std::max(MouthFramesFor(p.max_closure, hop_seconds), 2 * min_frames);
  piece_frames = MouthFramesFor(kPieceSeconds, hop_seconds);
  frame.resize(analyzer.window_samples());
  raw.reserve(2 * median_half + 2);
  shapes.reserve(delay_frames + 2);
  runs.reserve(delay_frames + 3);
}

template <typename Sample>
void RoughMouthStream::State::Push(std::span<const Sample> input, std::vector<Phoneme>& out) {
  if (hop == 0) return;
  for (const Sample s : input) samples.push_back(MouthSample(s));
  samples_total += input.size();
  AnalyzeFrames(false);
  SmoothFrames(false);
  CommitFrames(false, out);
}

void RoughMouthStream::State::Finish(std::vector<Phoneme>& out) {
  if (hop == 0) return;
  AnalyzeFrames(true);
  SmoothFrames(true);
  CommitFrames(true, out);
  if (piece_count > 0) EmitPiece(double(samples_total) / sample_rate, out);
  Reset();
}

// Frame i is centred on sample i * hop, zero outside the line (as AnalyzeMouthFrames).
void RoughMouthStream::State::AnalyzeFrames(bool flush) {
  const std::size_t window = frame.size();
  const std::size_t half = window / 2;
  const std::size_t total_frames = (samples_total + hop - 1) / hop;
  while (analyzed < total_frames && (flush || analyzed * hop + window - half <= samples_total)) {
    const std::ptrdiff_t first = std::ptrdiff_t(analyzed * hop) - std::ptrdiff_t(half);
    for (std::size_t j = 0; j < window; ++j) {
      const std::ptrdiff_t at = first + std::ptrdiff_t(j) - std::ptrdiff_t(samples_start);
      frame[j] = at >= 0 && std::size_t(at) < samples.size() ? samples[std::size_t(at)] : 0.0f;
    }
    raw.push_back(analyzer.Analyze(frame));
    ++analyzed;
    // Samples before the next frame's window are no longer needed.
    const std::size_t keep_from = analyzed * hop > half ? analyzed * hop - half : 0;
    if (keep_from > samples_start + 4 * window) {
      const std::size_t drop = std::min(keep_from - samples_start, samples.size());
      samples.erase(samples.begin(), samples.begin() + std::ptrdiff_t(drop));
      samples_start += drop;
    }
  }
}

// Median over frames [j - half, j + half], clipped to the line (as the whole-buffer filter).
void RoughMouthStream::State::SmoothFrames(bool flush) {
  while (smoothed < analyzed && (flush || smoothed + median_half < analyzed)) {
    const std::size_t first = smoothed >= median_half ? smoothed - median_half : 0;
    const std::size_t end = std::min(analyzed, smoothed + median_half + 1);
    Classify(MedianMouthFeatures(std::span<const MouthFrameFeatures>(raw).subspan(
        first - raw_start, end - first)));
    ++smoothed;
    const std::size_t needed_from = smoothed >= median_half ? smoothed - median_half : 0;
    if (needed_from > raw_start) {
      raw.erase(raw.begin(), raw.begin() + std::ptrdiff_t(needed_from - raw_start));
      raw_start = needed_from;
    }
  }
}

void RoughMouthStream::State::Classify(const MouthFrameFeatures& f) {
  if (!have_levels) {
    floor_db = loud_db = f.level_db;
    have_levels = true;
  }
  floor_db = std::min(f.level_db, floor_db + params.floor_rise_db_per_second * float(hop_seconds));
  loud_db = std::max(f.level_db, loud_db - params.loud_fall_db_per_second * float(hop_seconds));
  const MouthVoiceThresholds thresholds = MouthVoiceThresholdsFor(floor_db, loud_db, params);
  voiced = f.level_db > (voiced ? thresholds.off : thresholds.on);
  shapes.push_back(voiced ? VoicedMouthShape(f, params) : MouthShape::kRest);
}

void RoughMouthStream::State::CommitFrames(bool flush, std::vector<Phoneme>& out) {
  while (!shapes.empty() && (flush || shapes.size() > delay_frames)) {
    const MouthShape symbol = FrontSymbol();
    if (piece_count > 0 && (symbol != piece_symbol || piece_count >= piece_frames)) {
      EmitPiece((double(committed) - 0.5) * hop_seconds, out);
    }
    piece_symbol = symbol;
    ++piece_count;
    shapes.erase(shapes.begin());
    ++committed;
  }
}

// The phoneme of the oldest uncommitted frame: its run's class after merging
// the short runs in view, a silent run split into closure and rest by length.
MouthShape RoughMouthStream::State::FrontSymbol() {
  runs.clear();
  std::size_t front_at = 0;  // position of the front frame among the runs' frames
  if (run_count > 0) {
    // The committed run cannot change: long enough never to be merged away.
    runs.push_back({run_shape, 0, std::max(run_count, min_frames)});
    front_at = runs.back().count;
  }
  AppendMouthRuns(shapes, front_at, runs);
  MergeShortMouthRuns(runs, min_frames);
  std::size_t index = 0;
  while (runs[index].first + runs[index].count <= front_at) ++index;
  const MouthRun& run = runs[index];
  const bool continues = run_count > 0 && run.shape == run_shape;
  MouthShape symbol = run.shape;
  if (continues) {
    symbol = run_symbol;
  } else if (IsSilentMouth(run.shape)) {
    const bool ends_in_view = index + 1 < runs.size();
    const bool after_sound = committed > 0;
    const bool short_gap = double(run.count) * hop_seconds < params.max_closure;
    symbol = after_sound && ends_in_view && short_gap ? MouthShape::kClosed : MouthShape::kRest;
  }
  run_count = continues ? run_count + 1 : 1;
  run_shape = run.shape;
  run_symbol = symbol;
  return symbol;
}

void RoughMouthStream::State::EmitPiece(double end, std::vector<Phoneme>& out) {
  const double line_end = double(samples_total) / sample_rate;
  end = std::clamp(end, emitted_end, std::max(line_end, emitted_end));
  Phoneme phoneme;
  phoneme.start = Seconds(emitted_end);
  phoneme.duration = Seconds(end - emitted_end);
  phoneme.symbol.assign(RoughMouthSymbol(piece_symbol));
  phoneme.language = params.language;
  out.push_back(phoneme);
  emitted_end = end;
  piece_count = 0;
}

void RoughMouthStream::State::Reset() {
  samples.clear();
  samples_start = samples_total = 0;
  raw.clear();
  raw_start = analyzed = smoothed = 0;
  have_levels = voiced = false;
  shapes.clear();
  committed = run_count = piece_count = 0;
  emitted_end = 0.0;
}

RoughMouthStream::RoughMouthStream(int sample_rate, const AudioMouthParams& params)
    : state_(std::make_unique<State>(sample_rate, params)) {}
RoughMouthStream::~RoughMouthStream() = default;
RoughMouthStream::RoughMouthStream(RoughMouthStream&&) noexcept = default;
RoughMouthStream& RoughMouthStream::operator=(RoughMouthStream&&) noexcept = default;

bool RoughMouthStream::valid() const { return state_ && state_->hop > 0; }

double RoughMouthStream::latency() const {
  if (!valid()) return 0.0;
  const State& s = *state_;
  // Frames wait for the window's second half, the median's later frames, the
  // segment look-ahead and a whole piece.
  const double frames = double(s.median_half + s.delay_frames + s.piece_frames + 1);
  return frames * s.hop_seconds + 0.5 * double(s.frame.size()) / s.sample_rate;
}

void RoughMouthStream::Push(std::span<const float> samples, std::vector<Phoneme>& out) {
  if (state_) state_->Push(samples, out);
}

void RoughMouthStream::Push(std::span<const std::int16_t> samples, std::vector<Phoneme>& out) {
  if (state_) state_->Push(samples, out);
}

void RoughMouthStream::Finish(std::vector<Phoneme>& out) {
  if (state_) state_->Finish(out);
}

}  // namespace facerig
