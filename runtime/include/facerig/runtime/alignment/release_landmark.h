// The release of a /p b m/ lip closure as the audio shows it: the steepest
// rise of the log energy where the closure (silence, voice bar or nasal
// murmur) opens into the next sound. The aligners carry each bilabial across
// the warping path; one the path squeezed to no time moves onto the
// recording's own release, found the same way in the reference and in the
// recording so that the features' smearing cancels.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

// Shorter than this share of a frame, an aligned bilabial is squeezed: the
// path climbed through it without giving it time, so its place means little
// and the release decides it. Longer ones keep the warped timing, which the
// release (its landmark is good to about 20 ms) would not improve.
inline constexpr double kSqueezedFrames = 0.1;
// How far from the warped release the recording's own is looked for.
inline constexpr double kReleaseReachSeconds = 0.040;
// How far from ReleaseTime the reference's release is looked for.
inline constexpr double kReferenceReleaseReach = 0.015;
// The reference's release rises at least this much (natural log of the
// energy, between neighbouring frames).
inline constexpr double kMinReleaseRise = 0.2;
// The recording's rise must reach this share of the reference's.
inline constexpr double kReleaseRiseShare = 0.5;

struct EnergyRise {
  double position = 0.0;  // fractional frame index of the steepest rise (between two frames)
  double rise = 0.0;      // log-energy increase from the frame before to the frame after
};

// The steepest rise whose position lies in [first, last] (fractional frame
// indices); nullopt when the range holds no pair of frames.
std::optional<EnergyRise> SteepestRise(std::span<const float> log_energy, double first, double last);

// Where a bilabial's release lies on its own timeline: an unvoiced stop's
// event is its burst (the closure precedes it), b and m release at their end.
double ReleaseTime(const Phoneme& phoneme, std::string_view line_language);

// The viseme of `phoneme` (in its own language, else `line_language`) is PP.
bool IsBilabial(const Phoneme& phoneme, std::string_view line_language);

}  // namespace facerig
