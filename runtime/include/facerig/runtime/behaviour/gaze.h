// Idle gaze: the eyes jump (saccade) to a new target every min..max seconds,
// mostly small glances around the centre and now and then back to it, each
// jump a ~40 ms smoothstep. GazeJob advances a per-character GazeState and
// writes the eyeLook* channel values (weight_channels.h). Deterministic for a
// seed; a time going backwards (a seek) restarts the sequence from the seed.
#pragma once

#include <array>
#include <cstdint>

#include "facerig/runtime/behaviour/blink.h"  // Pcg32

namespace facerig {

struct GazeParams {
  bool enabled = true;
  double saccade_min_interval = 0.5;  // seconds between saccades, uniform in [min, max]
  double saccade_max_interval = 3.0;
  double saccade_duration = 0.04;     // seconds
  float recentre_probability = 0.3f;  // chance that a saccade goes back to the centre
  float amplitude = 0.35f;            // eyeLook* weight at the largest target

  // True when every value is finite and in range (0 < min <= max, duration > 0,
  // probability and amplitude in [0,1]).
  bool Valid() const;
};

// Where the eyes look: x to the character's right (+) / left (-), y up (+) /
// down (-); the targets lie in [-1,1] x [-0.6,0.6].
struct Gaze {
  float x = 0.0f;
  float y = 0.0f;
};

// eyeLook{In,Out,Up,Down}_{L,R}, the order of GazeChannels.
enum GazeShape : std::uint8_t { kLookInL, kLookOutL, kLookUpL, kLookDownL, kLookInR, kLookOutR, kLookUpR, kLookDownR };
inline constexpr std::size_t kGazeShapeCount = 8;
using GazeChannels = std::array<float, kGazeShapeCount>;
// ARKit names, indexed by GazeShape.
extern const std::array<const char*, kGazeShapeCount> kGazeShapeNames;

class GazeState {
 public:
  explicit GazeState(std::uint64_t seed = 0);
  Gaze gaze() const { return gaze_; }

 private:
  friend struct GazeJob;
  void Restart(const GazeParams& params);

  std::uint64_t seed_ = 0;
  Pcg32 rng_;
  bool started_ = false;
  double last_time_ = 0.0;
  double next_saccade_ = 0.0;
  double saccade_start_ = 0.0;
  Gaze from_, to_, gaze_;
};

enum class GazeError : std::uint8_t { kNone, kNoParams, kInvalidParams, kNoState, kNoOutput, kNonFiniteTime };

const char* ToString(GazeError error);

// Per frame: O(1) (plus one step per saccade due since the last Run); no
// allocation, exception or lock.
struct GazeJob {
  const GazeParams* params = nullptr;
  GazeState* state = nullptr;
  Seconds time{0.0};  // on the animation clock
  GazeChannels* out_channels = nullptr;

  GazeError Validate() const;
  // Validates, advances the state to `time` and writes the eyeLook* values
  // (all 0 when params->enabled is false). On error nothing changes.
  GazeError Run() const;
};

}  // namespace facerig
