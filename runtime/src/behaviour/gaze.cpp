#include "facerig/runtime/behaviour/gaze.h"

#include <algorithm>
#include <cmath>

namespace facerig {
namespace {

// Its own stream, so gaze and blinks from one seed are independent.
constexpr std::uint64_t kGazeStream = 0x6a09e667f3bcc909ULL;

float SmoothStep(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

double Interval(const GazeParams& params, Pcg32& rng) {
  return params.saccade_min_interval + rng.NextDouble() * (params.saccade_max_interval - params.saccade_min_interval);
}

}  // namespace

const std::array<const char*, kGazeShapeCount> kGazeShapeNames = {
    "eyeLookIn_L", "eyeLookOut_L", "eyeLookUp_L", "eyeLookDown_L",
    "eyeLookIn_R", "eyeLookOut_R", "eyeLookUp_R", "eyeLookDown_R"};

bool GazeParams::Valid() const {
  return std::isfinite(saccade_min_interval) && std::isfinite(saccade_max_interval) && saccade_min_interval > 0.0 &&
         saccade_max_interval >= saccade_min_interval && std::isfinite(saccade_duration) && saccade_duration > 0.0 &&
         recentre_probability >= 0.0f && recentre_probability <= 1.0f && amplitude >= 0.0f && amplitude <= 1.0f;
}

const char* ToString(GazeError error) {
  switch (error) {
    case GazeError::kNone: return "no error";
    case GazeError::kNoParams: return "no gaze params";
    case GazeError::kInvalidParams: return "gaze params out of range";
    case GazeError::kNoState: return "no gaze state";
    case GazeError::kNoOutput: return "no gaze output";
    case GazeError::kNonFiniteTime: return "time is NaN or infinite";
  }
  return "unknown error";
}

GazeState::GazeState(std::uint64_t seed) : seed_(seed), rng_(seed, kGazeStream) {}

void GazeState::Restart(const GazeParams& params) {
  rng_.Seed(seed_, kGazeStream);
  from_ = to_ = gaze_ = Gaze{};
  saccade_start_ = 0.0;
  next_saccade_ = Interval(params, rng_);
  started_ = true;
}

GazeError GazeJob::Validate() const {
  if (params == nullptr) return GazeError::kNoParams;
  if (!params->Valid()) return GazeError::kInvalidParams;
  if (state == nullptr) return GazeError::kNoState;
  if (out_channels == nullptr) return GazeError::kNoOutput;
  if (!std::isfinite(time.count())) return GazeError::kNonFiniteTime;
  return GazeError::kNone;
}

GazeError GazeJob::Run() const {
  if (const GazeError e = Validate(); e != GazeError::kNone) return e;
  GazeState& s = *state;
  const double now = time.count();
  if (!s.started_ || now < s.last_time_) s.Restart(*params);
  s.last_time_ = now;
  while (now >= s.next_saccade_) {
    s.from_ = s.to_;
    const bool recentre = s.rng_.NextDouble() < static_cast<double>(params->recentre_probability);
    s.to_.x = recentre ? 0.0f : static_cast<float>(s.rng_.NextDouble() * 2.0 - 1.0);
    s.to_.y = recentre ? 0.0f : static_cast<float>(s.rng_.NextDouble() * 1.2 - 0.6);
    s.saccade_start_ = s.next_saccade_;
    s.next_saccade_ += Interval(*params, s.rng_);
  }
  const float t = SmoothStep(static_cast<float>((now - s.saccade_start_) / params->saccade_duration));
  s.gaze_ = {s.from_.x + (s.to_.x - s.from_.x) * t, s.from_.y + (s.to_.y - s.from_.y) * t};

  const float a = params->enabled ? params->amplitude : 0.0f;
  const float right = std::max(s.gaze_.x, 0.0f) * a, left = std::max(-s.gaze_.x, 0.0f) * a;
  const float up = std::max(s.gaze_.y, 0.0f) * a, down = std::max(-s.gaze_.y, 0.0f) * a;
  // Looking to the character's left: the left eye looks out, the right eye in.
  *out_channels = {right, left, up, down, left, right, up, down};
  return GazeError::kNone;
}

}  // namespace facerig
