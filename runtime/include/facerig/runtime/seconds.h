// The speech timeline's one time type: phoneme and viseme-key times, a line's
// start and the animation clock handed to Character. A std::chrono duration
// of double seconds, so other units (milliseconds, audio samples through
// SamplesToSeconds) convert exactly and a bare number does not pass silently.
#pragma once

#include <chrono>
#include <cstddef>

namespace facerig {

using Seconds = std::chrono::duration<double>;

// The time of sample `samples` of audio at `sample_rate` Hz (0 when the rate is not positive).
inline Seconds SamplesToSeconds(std::size_t samples, int sample_rate) {
  return sample_rate > 0 ? Seconds(static_cast<double>(samples) / sample_rate) : Seconds(0.0);
}

}  // namespace facerig
