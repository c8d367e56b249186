// Doubtful lid landmarks (DoubtfulLidPoints, face_landmarks.h): the detector
// put them on the eyeball or tear film, where the lid is or 3-6 mm off it.
// Trusted, the wrong ones drag the template's lid across the eye and its
// blink tears; dropped, the lid of some faces is left without a hold. No
// fixed weight holds on every face (docs/benchmarks.md), so the rig is built
// both ways and the build whose blinks stretch the target's edges least is
// kept: a measure of the built rig alone.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "facerig/offline/landmarks/face_landmarks.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/offline/rigging/template_preparation.h"

namespace facerig {

// The worst edge stretch (moved length over rest length, at least 1) over
// the rig's eye-blink shapes (eyeBlink in any spelling, either side) at
// weight 1; nullopt when it has none.
std::optional<float> WorstBlinkStretch(const RawRig& rig);

// `landmarks` with the doubtful points put back at their detected confidence.
FaceLandmarks TrustingDoubtfulLids(const FaceLandmarks& landmarks, const DoubtfulLidPoints& doubtful);

struct LidChoice {
  bool tried = false;    // there were doubtful points and blinks to judge by: two builds
  bool trusted = false;  // the kept build trusts the doubtful points
  // WorstBlinkStretch of each build; 0 for a build that failed (its error
  // is thrown only when both failed).
  float trusted_stretch = 0.0f, dropped_stretch = 0.0f;
};

// BuildRig with `landmarks` (the doubtful points left out, as the detector
// returns them) and, when there are doubtful points and the template has
// blinks, at the same time with them trusted; returns the build whose
// blinks stretch least. `choice` (optional) says what was done.
// \throw what BuildRig throws, the build without the doubtful points' error
//        when both fail.
BuildRigResult BuildRigChoosingLids(const TemplatePreparation& prepared, const BuildTarget& target,
                                    const std::vector<std::uint32_t>& template_vertex_of,
                                    const FaceLandmarks& landmarks, const DoubtfulLidPoints& doubtful,
                                    const BuildRigParams& params, LidChoice* choice = nullptr);

}  // namespace facerig
