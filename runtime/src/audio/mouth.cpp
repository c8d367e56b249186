#include "facerig/runtime/audio/mouth.h"

#include <algorithm>
#include <cmath>

#include "audio/mouth_segments.h"
#include "audio/percentile.h"

namespace facerig {
namespace {

std::vector<MouthFrameFeatures> MedianFiltered(std::span<const MouthFrameFeatures> frames,
                                               const AudioMouthParams& params) {
  const std::size_t half = static_cast<std::size_t>(MouthMedianFrames(params) / 2);
  std::vector<MouthFrameFeatures> out;
  out.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::size_t first = i >= half ? i - half : 0;
    const std::size_t end = std::min(frames.size(), i + half + 1);
    out.push_back(MedianMouthFeatures(frames.subspan(first, end - first)));
  }
  return out;
}

MouthVoiceThresholds WholeBufferThresholds(std::span<const MouthFrameFeatures> frames,
                                           const AudioMouthParams& params) {
  std::vector<float> levels;
  levels.reserve(frames.size());
  for (const MouthFrameFeatures& f : frames) levels.push_back(f.level_db);
  const float floor = detail::PercentileInPlace(levels, 0.02);
  const float loud = detail::PercentileInPlace(levels, 0.95);
  return MouthVoiceThresholdsFor(floor, loud, params);
}

template <typename Sample>
std::optional<SpeechLine> Rough(std::span<const Sample> samples, int sample_rate,
                                const AudioMouthParams& params) {
  const std::size_t hop = MouthHopSamples(sample_rate, params.analysis);
  if (hop == 0) return std::nullopt;
  SpeechLine line;
  line.language = params.language;
  const std::vector<MouthFrameFeatures> frames =
      AnalyzeMouthFrames(samples, sample_rate, params.analysis);
  const std::vector<MouthShape> shapes = ClassifyMouthFrames(frames, params);
  line.phonemes = MouthShapesToPhonemes(shapes, double(hop) / sample_rate,
                                        SamplesToSeconds(samples.size(), sample_rate).count(),
                                        params);
  return line;
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
  const std::vector<MouthFrameFeatures> smooth = MedianFiltered(frames, params);
  const MouthVoiceThresholds thresholds = WholeBufferThresholds(smooth, params);
  shapes.reserve(smooth.size());
  bool voiced = false;
  for (const MouthFrameFeatures& f : smooth) {
    voiced = f.level_db > (voiced ? thresholds.off : thresholds.on);
    shapes.push_back(voiced ? VoicedMouthShape(f, params) : MouthShape::kRest);
  }
  return shapes;
}

std::vector<Phoneme> MouthShapesToPhonemes(std::span<const MouthShape> shapes, double hop_seconds,
                                           double duration, const AudioMouthParams& params) {
  std::vector<Phoneme> phonemes;
  if (shapes.empty() || !std::isfinite(hop_seconds) || hop_seconds <= 0.0) return phonemes;
  if (!std::isfinite(duration) || duration < 0.0) duration = 0.0;
  std::vector<MouthRun> runs;
  AppendMouthRuns(shapes, 0, runs);
  MergeShortMouthRuns(runs, MouthFramesFor(params.min_segment, hop_seconds));
  phonemes.reserve(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const MouthRun& run = runs[i];
    const double boundary = (double(run.first) - 0.5) * hop_seconds;
    const double next_boundary = (double(run.first + run.count) - 0.5) * hop_seconds;
    const double start = i == 0 ? 0.0 : std::clamp(boundary, 0.0, duration);
    const double end = i + 1 == runs.size() ? std::max(duration, start)
                                            : std::clamp(next_boundary, start, duration);
    MouthShape shape = run.shape;
    if (IsSilentMouth(shape)) {
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

std::optional<SpeechLine> RoughMouthFromAudio(std::span<const float> samples, int sample_rate,
                                              const AudioMouthParams& params) {
  return Rough(samples, sample_rate, params);
}

std::optional<SpeechLine> RoughMouthFromAudio(std::span<const std::int16_t> samples,
                                              int sample_rate, const AudioMouthParams& params) {
  return Rough(samples, sample_rate, params);
}

}  // namespace facerig
