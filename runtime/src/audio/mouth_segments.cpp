#include "audio/mouth_segments.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace facerig {

int MouthMedianFrames(const AudioMouthParams& params) {
  const int frames = std::clamp(params.median_frames, 1, kMaxMouthMedianFrames);
  return frames % 2 == 1 ? frames : frames - 1;
}

MouthFrameFeatures MedianMouthFeatures(std::span<const MouthFrameFeatures> frames) {
  std::array<float, kMaxMouthMedianFrames> values{};
  const std::size_t n = std::min<std::size_t>(frames.size(), kMaxMouthMedianFrames);
  if (n == 0) return {};
  auto median = [&](auto&& get) {
    for (std::size_t i = 0; i < n; ++i) values[i] = get(frames[i]);
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(values.begin(), middle, values.begin() + static_cast<std::ptrdiff_t>(n));
    return *middle;
  };
  MouthFrameFeatures out;
  out.level_db = median([](const MouthFrameFeatures& f) { return f.level_db; });
  for (std::size_t b = 0; b < kMouthBandCount; ++b) {
    out.band_db[b] = median([b](const MouthFrameFeatures& f) { return f.band_db[b]; });
  }
  return out;
}

MouthVoiceThresholds MouthVoiceThresholdsFor(float floor_db, float loud_db,
                                             const AudioMouthParams& params) {
  const float lowest = loud_db - params.max_below_loud_db;
  const float highest = std::max(lowest, loud_db - params.min_below_loud_db);
  float on = std::clamp(floor_db + params.above_floor_db, lowest, highest);
  // A recording of noise alone (loud close to the floor) stays silent.
  on = std::max({on, floor_db + params.min_above_floor_db, params.min_voice_db});
  return {on, on - std::max(params.hysteresis_db, 0.0f)};
}

MouthShape VoicedMouthShape(const MouthFrameFeatures& f, const AudioMouthParams& params) {
  const float low = f.band(MouthBand::kLowFormant);
  const float high = f.band(MouthBand::kHighFormant);
  const float back = f.band(MouthBand::kBackFormant);
  const float front = f.band(MouthBand::kFrontFormant);
  if (f.band(MouthBand::kFrication) - std::max({low, high, back, front}) > params.fricative_db) {
    return MouthShape::kFricative;
  }
  if (front - back > params.front_over_back_db && front - high > params.front_over_high_db) {
    return MouthShape::kFront;
  }
  if (high - low > params.open_db) return MouthShape::kOpen;
  return MouthShape::kRounded;
}

void AppendMouthRuns(std::span<const MouthShape> shapes, std::size_t first_frame,
                     std::vector<MouthRun>& runs) {
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (!runs.empty() && runs.back().shape == shapes[i]) {
      ++runs.back().count;
    } else {
      runs.push_back({shapes[i], first_frame + i, 1});
    }
  }
}

namespace {

void JoinEqualNeighbours(std::vector<MouthRun>& runs) {
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

}  // namespace

void MergeShortMouthRuns(std::vector<MouthRun>& runs, std::size_t min_frames) {
  while (runs.size() > 1) {
    std::size_t shortest = runs.size();
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (runs[i].count < min_frames &&
          (shortest == runs.size() || runs[i].count < runs[shortest].count)) {
        shortest = i;
      }
    }
    if (shortest == runs.size()) return;
    const std::size_t before = shortest > 0 ? runs[shortest - 1].count : 0;
    const std::size_t after = shortest + 1 < runs.size() ? runs[shortest + 1].count : 0;
    runs[shortest].shape = before >= after ? runs[shortest - 1].shape : runs[shortest + 1].shape;
    JoinEqualNeighbours(runs);
  }
}

std::size_t MouthFramesFor(double seconds, double hop_seconds) {
  if (!std::isfinite(seconds) || !std::isfinite(hop_seconds) || hop_seconds <= 0.0) return 1;
  return static_cast<std::size_t>(std::clamp(std::ceil(seconds / hop_seconds - 1e-9), 1.0, 1e6));
}

}  // namespace facerig
