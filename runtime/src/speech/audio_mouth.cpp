#include "facerig/runtime/speech/audio_mouth.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace facerig {
namespace {

constexpr int kMaxMedianFrames = 31;

// The value at `fraction` (0..1) of the sorted levels.
float Percentile(std::vector<float> levels, double fraction) {
  const auto at = static_cast<std::size_t>(fraction * double(levels.size() - 1));
  std::nth_element(levels.begin(), levels.begin() + static_cast<std::ptrdiff_t>(at), levels.end());
  return levels[at];
}

// Median of each feature over a window of frames centred on each frame.
std::vector<MouthFrameFeatures> MedianFiltered(std::span<const MouthFrameFeatures> frames,
                                               int window) {
  std::vector<MouthFrameFeatures> out(frames.begin(), frames.end());
  window = std::clamp(window, 1, kMaxMedianFrames);
  const auto half = static_cast<std::ptrdiff_t>(window / 2);
  if (half == 0) return out;
  const auto count = static_cast<std::ptrdiff_t>(frames.size());
  std::array<float, kMaxMedianFrames> values{};
  auto median = [&](std::ptrdiff_t i, auto&& get) {
    const std::ptrdiff_t first = std::max<std::ptrdiff_t>(0, i - half);
    const std::ptrdiff_t last = std::min(count - 1, i + half);
    std::size_t n = 0;
    for (std::ptrdiff_t j = first; j <= last; ++j) values[n++] = get(frames[std::size_t(j)]);
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(n / 2), values.begin() + std::ptrdiff_t(n));
    return values[n / 2];
  };
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    MouthFrameFeatures& f = out[std::size_t(i)];
    f.level_db = median(i, [](const MouthFrameFeatures& x) { return x.level_db; });
    for (std::size_t b = 0; b < kMouthBandCount; ++b) {
      f.band_db[b] = median(i, [b](const MouthFrameFeatures& x) { return x.band_db[b]; });
    }
  }
  return out;
}

struct VoiceThresholds {
  float on = 0.0f;
  float off = 0.0f;
};

VoiceThresholds VoiceThresholdsFor(std::span<const MouthFrameFeatures> frames,
                                   const AudioMouthParams& params) {
  std::vector<float> levels;
  levels.reserve(frames.size());
  for (const MouthFrameFeatures& f : frames) levels.push_back(f.level_db);
  const float floor = Percentile(levels, 0.02);
  const float loud = Percentile(std::move(levels), 0.95);
  float on = std::clamp(floor + params.above_floor_db, loud - params.max_below_loud_db,
                        std::max(loud - params.max_below_loud_db, loud - params.min_below_loud_db));
  on = std::max(on, params.min_voice_db);
  return {on, on - std::max(params.hysteresis_db, 0.0f)};
}

MouthShape VoicedShape(const MouthFrameFeatures& f, const AudioMouthParams& params) {
  const float low = f.band(MouthBand::kLowFormant);
  const float high = f.band(MouthBand::kHighFormant);
  const float back = f.band(MouthBand::kBackFormant);
  const float front = f.band(MouthBand::kFrontFormant);
  const float strongest_formant = std::max({low, high, back, front});
  if (f.band(MouthBand::kFrication) - strongest_formant > params.fricative_db) {
    return MouthShape::kFricative;
  }
  if (front - back > params.front_over_back_db && front - high > params.front_over_high_db) return MouthShape::kFront;
  if (high - low > params.open_db) return MouthShape::kOpen;
  return MouthShape::kRounded;
}

struct Run {
  MouthShape shape;
  std::size_t first;
  std::size_t count;
};

bool IsSilent(MouthShape shape) { return shape == MouthShape::kRest || shape == MouthShape::kClosed; }

std::vector<Run> RunsOf(std::span<const MouthShape> shapes) {
  std::vector<Run> runs;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (!runs.empty() && runs.back().shape == shapes[i]) {
      ++runs.back().count;
    } else {
      runs.push_back({shapes[i], i, 1});
    }
  }
  return runs;
}

// Joins neighbouring runs of the same shape.
void Coalesce(std::vector<Run>& runs) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (kept > 0 && runs[kept - 1].shape == runs[i].shape) {
      runs[kept - 1].count += runs[i].count;
    } else {
      runs[kept++] = runs[i];
    }
  }
  runs.resize(kept);
}

// Gives every run shorter than min_frames the shape of its longer neighbour,
// the shortest run first, until none is left (or one run remains).
void MergeShortRuns(std::vector<Run>& runs, std::size_t min_frames) {
  while (runs.size() > 1) {
    std::size_t shortest = runs.size();
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (runs[i].count < min_frames && (shortest == runs.size() || runs[i].count < runs[shortest].count)) {
        shortest = i;
      }
    }
    if (shortest == runs.size()) return;
    const std::size_t before = shortest > 0 ? runs[shortest - 1].count : 0;
    const std::size_t after = shortest + 1 < runs.size() ? runs[shortest + 1].count : 0;
    runs[shortest].shape = before >= after ? runs[shortest - 1].shape : runs[shortest + 1].shape;
    Coalesce(runs);
  }
}

}  // namespace

std::string_view RoughMouthSymbol(MouthShape shape) {
  switch (shape) {
    case MouthShape::kRest: return "_";
    case MouthShape::kClosed: return "b";
    case MouthShape::kOpen: return "a";
    case MouthShape::kFront: return "i";
    case MouthShape::kRounded: return "o";
    case MouthShape::kFricative: return "s";
  }
  return "_";
}

std::vector<MouthShape> ClassifyMouthFrames(std::span<const MouthFrameFeatures> frames,
                                            const AudioMouthParams& params) {
  std::vector<MouthShape> shapes;
  if (frames.empty()) return shapes;
  const std::vector<MouthFrameFeatures> smooth = MedianFiltered(frames, params.median_frames);
  const VoiceThresholds thresholds = VoiceThresholdsFor(smooth, params);
  shapes.reserve(smooth.size());
  bool voiced = false;
  for (const MouthFrameFeatures& f : smooth) {
    voiced = f.level_db > (voiced ? thresholds.off : thresholds.on);
    shapes.push_back(voiced ? VoicedShape(f, params) : MouthShape::kRest);
  }
  return shapes;
}

std::vector<Phoneme> MouthShapesToPhonemes(std::span<const MouthShape> shapes, double hop_seconds,
                                           double duration, const AudioMouthParams& params) {
  std::vector<Phoneme> phonemes;
  if (shapes.empty() || !std::isfinite(hop_seconds) || hop_seconds <= 0.0) return phonemes;
  if (!std::isfinite(duration) || duration < 0.0) duration = 0.0;
  std::vector<Run> runs = RunsOf(shapes);
  const double min_frames = std::isfinite(params.min_segment) ? params.min_segment / hop_seconds : 0.0;
  MergeShortRuns(runs, static_cast<std::size_t>(std::clamp(std::ceil(min_frames - 1e-9), 1.0, 1e6)));
  phonemes.reserve(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Run& run = runs[i];
    const double start = i == 0 ? 0.0 : std::clamp((double(run.first) - 0.5) * hop_seconds, 0.0, duration);
    const double end = i + 1 == runs.size()
                           ? std::max(duration, start)
                           : std::clamp((double(run.first + run.count) - 0.5) * hop_seconds, start, duration);
    MouthShape shape = run.shape;
    if (IsSilent(shape)) {
      const bool inside = i > 0 && i + 1 < runs.size();
      shape = inside && end - start < params.max_closure ? MouthShape::kClosed : MouthShape::kRest;
    }
    Phoneme phoneme;
    phoneme.start = Seconds(start);
    phoneme.duration = Seconds(end - start);
    phoneme.symbol.assign(RoughMouthSymbol(shape));
    phoneme.language = params.language;
    phonemes.push_back(phoneme);
  }
  return phonemes;
}

namespace {

template <typename Sample>
std::optional<SpeechLine> Rough(std::span<const Sample> samples, int sample_rate,
                                const AudioMouthParams& params) {
  const std::size_t hop = MouthHopSamples(sample_rate, params.analysis);
  if (hop == 0) return std::nullopt;
  SpeechLine line;
  line.language = params.language;
  const std::vector<MouthFrameFeatures> frames = AnalyzeMouthFrames(samples, sample_rate, params.analysis);
  const std::vector<MouthShape> shapes = ClassifyMouthFrames(frames, params);
  line.phonemes = MouthShapesToPhonemes(shapes, double(hop) / sample_rate,
                                        SamplesToSeconds(samples.size(), sample_rate).count(), params);
  return line;
}

}  // namespace

std::optional<SpeechLine> RoughMouthFromAudio(std::span<const float> samples, int sample_rate,
                                              const AudioMouthParams& params) {
  return Rough(samples, sample_rate, params);
}

std::optional<SpeechLine> RoughMouthFromAudio(std::span<const std::int16_t> samples,
                                              int sample_rate, const AudioMouthParams& params) {
  return Rough(samples, sample_rate, params);
}

}  // namespace facerig
