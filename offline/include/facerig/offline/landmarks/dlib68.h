// Names for the points of dlib's 68-point face model (the Multi-PIE / iBUG
// 300-W markup). "Right" and "left" are the subject's: the right eye (36-41)
// is on the image's left in a frontal photograph.
#pragma once

#include <cstddef>

namespace facerig::dlib68 {

inline constexpr std::size_t kCount = 68;

inline constexpr std::size_t kJawFirst = 0;  // jaw line, right ear to left ear
inline constexpr std::size_t kChin = 8;
inline constexpr std::size_t kJawLast = 16;
inline constexpr std::size_t kRightBrowFirst = 17;  // each brow: outer end to inner end
inline constexpr std::size_t kRightBrowPeak = 19;
inline constexpr std::size_t kRightBrowLast = 21;
inline constexpr std::size_t kLeftBrowFirst = 22;
inline constexpr std::size_t kLeftBrowPeak = 24;
inline constexpr std::size_t kLeftBrowLast = 26;
inline constexpr std::size_t kNoseTip = 30;  // the bridge is 27-30
inline constexpr std::size_t kNostrilsFirst = 31;
inline constexpr std::size_t kNostrilsLast = 35;
inline constexpr std::size_t kRightEyeFirst = 36;  // each eye: outer corner, upper lid, inner corner, lower lid
inline constexpr std::size_t kRightEyeLast = 41;
inline constexpr std::size_t kLeftEyeFirst = 42;  // inner corner first
inline constexpr std::size_t kLeftEyeLast = 47;
inline constexpr std::size_t kOuterLipsFirst = 48;  // right mouth corner
inline constexpr std::size_t kLeftMouthCorner = 54;
inline constexpr std::size_t kOuterLipsLast = 59;
inline constexpr std::size_t kInnerLipsFirst = 60;
inline constexpr std::size_t kInnerLipsLast = 67;

}  // namespace facerig::dlib68
