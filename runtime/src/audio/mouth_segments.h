// The decisions shared by the whole-buffer and the streaming rough mouth:
// median smoothing, the voice threshold, a voiced frame's class, and runs of
// equal shapes with short ones merged away. Private to facerig::runtime.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "facerig/runtime/audio/mouth.h"

namespace facerig {

inline constexpr int kMaxMouthMedianFrames = 31;

// params.median_frames clamped to [1, kMaxMouthMedianFrames], made odd.
int MouthMedianFrames(const AudioMouthParams& params);

// The per-feature median of `frames` (1..kMaxMouthMedianFrames of them).
MouthFrameFeatures MedianMouthFeatures(std::span<const MouthFrameFeatures> frames);

struct MouthVoiceThresholds {
  float on = 0.0f;   // silent -> voiced above this level
  float off = 0.0f;  // voiced -> silent below this level
};

// From the noise floor and the loud (vowel) level, as AudioMouthParams describes.
MouthVoiceThresholds MouthVoiceThresholdsFor(float floor_db, float loud_db,
                                             const AudioMouthParams& params);

// The class of a voiced frame (never kRest or kClosed).
MouthShape VoicedMouthShape(const MouthFrameFeatures& frame, const AudioMouthParams& params);

inline bool IsSilentMouth(MouthShape shape) {
  return shape == MouthShape::kRest || shape == MouthShape::kClosed;
}

struct MouthRun {
  MouthShape shape = MouthShape::kRest;
  std::size_t first = 0;  // frame index
  std::size_t count = 0;
};

// Appends the runs of equal shapes to `runs` (joining the last run there if
// its shape continues); frame indices start at `first_frame`.
void AppendMouthRuns(std::span<const MouthShape> shapes, std::size_t first_frame,
                     std::vector<MouthRun>& runs);

// Gives every run shorter than min_frames the shape of its longer neighbour
// (the earlier one on a tie), the shortest run first, until none is left or
// one run remains; neighbours of equal shape are joined.
void MergeShortMouthRuns(std::vector<MouthRun>& runs, std::size_t min_frames);

// A duration in frames, rounded up, at least 1.
std::size_t MouthFramesFor(double seconds, double hop_seconds);

}  // namespace facerig
