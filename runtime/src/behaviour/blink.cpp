#include "facerig/runtime/behaviour/blink.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "finite_range.h"

namespace facerig {

// --- Pcg32 -------------------------------------------------------------------

void Pcg32::Seed(std::uint64_t seed, std::uint64_t stream) {
  // The reference pcg32_srandom_r sequence.
  state_ = 0;
  increment_ = (stream << 1u) | 1u;
  Next();
  state_ += seed;
  Next();
}

std::uint32_t Pcg32::Next() {
  const std::uint64_t old = state_;
  state_ = old * 6364136223846793005ULL + increment_;
  const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
  const auto rotation = static_cast<std::uint32_t>(old >> 59u);
  return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
}

double Pcg32::NextDouble() {
  // Two calls in separate statements: their order must not be left to the compiler.
  const std::uint64_t high = Next();
  const std::uint64_t low = Next();
  return static_cast<double>(((high << 32u) | low) >> 11u) * 0x1.0p-53;
}

double Pcg32::NextNormal() {
  // Polar method: only +, *, log and sqrt, no cos/sin, so less libm in the
  // result; the second normal of the pair is dropped to keep the state small.
  for (;;) {
    const double u = 2.0 * NextDouble() - 1.0;
    const double v = 2.0 * NextDouble() - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * std::log(s) / s);
  }
}

// --- Params --------------------------------------------------------------------

const char* ToString(BlinkError error) {
  switch (error) {
    case BlinkError::kNone: return "no error";
    case BlinkError::kNoParams: return "no blink params";
    case BlinkError::kInvalidParams: return "blink params out of range";
    case BlinkError::kNoState: return "no blink state";
    case BlinkError::kNoOutput: return "an output pointer is null";
    case BlinkError::kNonFiniteTime: return "time is NaN or infinite";
    case BlinkError::kTimeWentBackwards: return "time is earlier than the previous frame's";
    case BlinkError::kInvalidInterval: return "invalid simulation interval or activity segments";
  }
  return "unknown error";
}

namespace {

// Numbers derived from BlinkParams, recomputed per Run (a few flops) so that
// the caller may edit the params between frames.
struct Derived {
  double gap_mu = 0.0;         // log-normal location of the gap beyond min_gap
  double talking_speed = 1.0;  // blink-clock speed while talking (rest = 1)
};

// Mean real time per blink that is not eyes-open gap: the blink itself and
// the eye offset, plus the double-blink gaps spread over all blinks.
// Every episode is one blink, or with probability q two blinks and a short
// gap, followed by one eyes-open gap; for a mean onset-to-onset interval of
// 60/rate, an episode lasts (1 + q) * 60 / rate.
double MeanGapFor(const BlinkParams& p, double rate_per_min) {
  const double mean_blink = (p.min_duration_seconds + p.mode_duration_seconds +
                             p.max_duration_seconds) / 3.0 + 0.5 * p.max_eye_offset_seconds;
  const double mean_double_gap = 0.5 * (p.min_double_gap_seconds + p.max_double_gap_seconds);
  const double q = p.double_blink_probability;
  return (1.0 + q) * (60.0 / rate_per_min - mean_blink) - q * mean_double_gap;
}

// Rest gaps need room beyond the refractory minimum; talking gaps are scaled
// by the clock speed, so they only need to be positive.
constexpr double kMinMeanGapBeyondMinimum = 0.05;

bool ComputeDerived(const BlinkParams& p, Derived* derived) {
  const double rest_gap = MeanGapFor(p, p.rest_rate_per_min);
  const double talking_gap = MeanGapFor(p, p.talking_rate_per_min);
  if (!(rest_gap - p.min_gap_seconds >= kMinMeanGapBeyondMinimum) ||
      !(talking_gap >= kMinMeanGapBeyondMinimum)) {
    return false;
  }
  derived->gap_mu = std::log(rest_gap - p.min_gap_seconds) - 0.5 * p.gap_log_sigma * p.gap_log_sigma;
  derived->talking_speed = rest_gap / talking_gap;
  return true;
}

double Smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

// Blink onsets, ends and double-blink starts one Run may pass through; with
// valid params a 1 s step holds far fewer.
constexpr int kMaxEventsPerStep = 64;
// SimulateBlinks steps like a 60 fps job.
constexpr double kSimulationStep = 1.0 / 60.0;

}  // namespace

bool BlinkParams::Validate() const {
  const bool fields_ok =
      InRange(rest_rate_per_min, 0.1, 240.0) && InRange(talking_rate_per_min, 0.1, 240.0) &&
      InRange(min_gap_seconds, 0.0, 60.0) && InRange(gap_log_sigma, 0.01, 3.0) &&
      InRange(min_duration_seconds, 0.02, 2.0) &&
      InRange(mode_duration_seconds, min_duration_seconds, max_duration_seconds) &&
      InRange(max_duration_seconds, min_duration_seconds, 2.0) &&
      InRange(min_close_open_ratio, 0.05, 20.0) &&
      InRange(max_close_open_ratio, min_close_open_ratio, 20.0) &&
      InRange(hold_fraction, 0.0, 0.5) && InRange(min_peak, 0.0, 1.0) &&
      InRange(max_eye_peak_difference, 0.0, 1.0) && InRange(max_eye_offset_seconds, 0.0, 0.1) &&
      InRange(double_blink_probability, 0.0, 0.5) && InRange(min_double_gap_seconds, 0.0, 2.0) &&
      InRange(max_double_gap_seconds, min_double_gap_seconds, 2.0) &&
      InRange(pause_hazard_boost, 1.0, 100.0) && InRange(prior_pause_fraction, 0.0, 0.99) &&
      InRange(pause_fraction_time_constant, 0.1, 3600.0) &&
      InRange(max_time_step_seconds, 1e-3, 1.0);
  Derived derived;
  return fields_ok && ComputeDerived(*this, &derived);
}

float BlinkClosure(const BlinkEvent& blink, double t, float peak) {
  if (!(t >= 0.0) || !(t < blink.duration)) return 0.0f;
  const double opening_start = blink.close_duration + blink.hold_duration;
  double closure = 1.0;  // held closed between closing and opening
  if (t < blink.close_duration) {
    closure = Smoothstep(t / blink.close_duration);
  } else if (t >= opening_start) {
    closure = 1.0 - Smoothstep(std::min((t - opening_start) / blink.open_duration, 1.0));
  }
  return static_cast<float>(closure) * peak;
}

// --- The state machine, shared by BlinkJob and SimulateBlinks ----------------

// Where SimulateBlinks collects the blinks that start in [start, end).
struct BlinkRecorder {
  std::span<BlinkEvent> out;
  double start = 0.0;
  double end = 0.0;
  std::size_t count = 0;
};

class BlinkEngine {
 public:
  static void Begin(BlinkState& s, const BlinkParams& p, const Derived& d, double time) {
    s.has_time_ = true;
    s.time_ = time;
    s.phase_ = BlinkState::Phase::kOpen;
    s.double_pending_ = false;
    s.pause_fraction_ = p.prior_pause_fraction;
    s.gap_ = DrawGap(s, p, d);
    // A random phase in the first interval, so that characters created at
    // the same moment do not all wait a full interval and then blink together.
    s.gap_elapsed_ = s.rng_.NextDouble() * s.gap_;
  }

  static void Step(BlinkState& s, const BlinkParams& p, const Derived& d, double time,
                   bool talking, bool at_pause, BlinkRecorder* recorder) {
    const double dt = time - s.time_;
    if (dt > p.max_time_step_seconds) {
      // Replaying the missed time would flash a burst of blinks (or leave the
      // eye mid-blink); start a fresh interval instead.
      Restart(s, p, d);
      s.time_ = time;
      return;
    }
    // Pause share at mid-step, so the speed barely depends on how time is
    // cut into frames.
    const double pause_target = at_pause ? 1.0 : 0.0;
    const double pause_keep = std::exp(-0.5 * dt / p.pause_fraction_time_constant);
    const double pause_fraction_mid = pause_target + (s.pause_fraction_ - pause_target) * pause_keep;
    const double speed = ClockSpeed(p, d, pause_fraction_mid, talking, at_pause);
    double t = s.time_;
    double open_time = 0.0;  // of this step, in the eyes-open phase
    int events = 0;
    for (; events < kMaxEventsPerStep; ++events) {
      if (s.phase_ == BlinkState::Phase::kOpen) {
        const double onset = t + (s.gap_ - s.gap_elapsed_) / speed;
        if (onset > time) {
          s.gap_elapsed_ += speed * (time - t);
          open_time += time - t;
          break;
        }
        StartBlink(s, p, onset, /*second_of_double=*/false, recorder);
        open_time += onset - t;
        t = onset;
      } else if (s.phase_ == BlinkState::Phase::kBlinking) {
        const double end = s.current_.end();
        if (end > time) break;
        t = end;
        if (s.double_pending_) {
          s.double_pending_ = false;
          s.phase_ = BlinkState::Phase::kDoubleWait;
          s.double_onset_ = end + s.double_gap_;
        } else {
          Restart(s, p, d);
        }
      } else {  // kDoubleWait
        if (s.double_onset_ > time) break;
        t = s.double_onset_;
        StartBlink(s, p, t, /*second_of_double=*/true, recorder);
      }
    }
    if (events == kMaxEventsPerStep) Restart(s, p, d);  // only with extreme params

    if (talking) {
      // Measured over eyes-open time only, the time the blink clock runs:
      // blinks fall mostly in pauses, and counting their closed time would
      // overweight pauses and slow the talking rate (~4% at k = 4).
      const double keep = std::exp(-open_time / p.pause_fraction_time_constant);
      s.pause_fraction_ = pause_target + (s.pause_fraction_ - pause_target) * keep;
    }
    s.time_ = time;
  }

  static void Evaluate(const BlinkState& s, double time, float* left, float* right) {
    if (s.phase_ != BlinkState::Phase::kBlinking) {
      *left = 0.0f;
      *right = 0.0f;
      return;
    }
    const BlinkEvent& b = s.current_;
    const double left_onset = b.start + std::max(0.0, -b.eye_offset);
    const double right_onset = b.start + std::max(0.0, b.eye_offset);
    *left = BlinkClosure(b, time - left_onset, b.peak_left);
    *right = BlinkClosure(b, time - right_onset, b.peak_right);
  }

 private:
  static double DrawGap(BlinkState& s, const BlinkParams& p, const Derived& d) {
    return p.min_gap_seconds + std::exp(d.gap_mu + p.gap_log_sigma * s.rng_.NextNormal());
  }

  static double ClockSpeed(const BlinkParams& p, const Derived& d, double pause_fraction,
                           bool talking, bool at_pause) {
    if (!talking) return 1.0;
    // Mean speed over talking time stays talking_speed whatever the pause
    // share f: speech gets 1 / (1 + f (k - 1)) of it and pauses k times that.
    const double k = p.pause_hazard_boost;
    const double f = std::clamp(pause_fraction, 0.0, 1.0);
    return d.talking_speed * (at_pause ? k : 1.0) / (1.0 + f * (k - 1.0));
  }

  // Eyes open, a fresh eyes-open gap from now.
  static void Restart(BlinkState& s, const BlinkParams& p, const Derived& d) {
    s.phase_ = BlinkState::Phase::kOpen;
    s.double_pending_ = false;
    s.gap_ = DrawGap(s, p, d);
    s.gap_elapsed_ = 0.0;
  }

  static double Uniform(BlinkState& s, double lo, double hi) {
    return lo + (hi - lo) * s.rng_.NextDouble();
  }

  static void StartBlink(BlinkState& s, const BlinkParams& p, double onset, bool second_of_double,
                         BlinkRecorder* recorder) {
    BlinkEvent b;
    b.start = onset;
    b.second_of_double = second_of_double;
    // Triangular duration by inverse CDF (sqrt only, so exactly reproducible).
    const double a = p.min_duration_seconds;
    const double c = p.mode_duration_seconds;
    const double e = p.max_duration_seconds;
    const double u = s.rng_.NextDouble();
    if (e > a) {
      const double mode_cdf = (c - a) / (e - a);
      b.duration = u < mode_cdf ? a + std::sqrt(u * (e - a) * (c - a))
                                : e - std::sqrt((1.0 - u) * (e - a) * (e - c));
    } else {
      b.duration = a;
    }
    const double ratio = Uniform(s, p.min_close_open_ratio, p.max_close_open_ratio);
    b.hold_duration = p.hold_fraction * b.duration;
    b.open_duration = (b.duration - b.hold_duration) / (1.0 + ratio);
    b.close_duration = b.duration - b.hold_duration - b.open_duration;

    const auto peak = static_cast<float>(Uniform(s, p.min_peak, 1.0));
    const double drop_left = Uniform(s, 0.0, p.max_eye_peak_difference);
    const double drop_right = Uniform(s, 0.0, p.max_eye_peak_difference);
    b.peak_left = std::clamp(peak - static_cast<float>(drop_left), 0.0f, 1.0f);
    b.peak_right = std::clamp(peak - static_cast<float>(drop_right), 0.0f, 1.0f);
    const double offset = Uniform(s, 0.0, p.max_eye_offset_seconds);
    b.eye_offset = (s.rng_.Next() & 1u) != 0 ? offset : -offset;

    // Drawn for every blink, so the random sequence does not depend on
    // which blinks were doubles.
    const double double_draw = s.rng_.NextDouble();
    const double double_gap = Uniform(s, p.min_double_gap_seconds, p.max_double_gap_seconds);
    s.double_pending_ = !second_of_double && double_draw < p.double_blink_probability;
    s.double_gap_ = double_gap;

    s.current_ = b;
    s.phase_ = BlinkState::Phase::kBlinking;
    ++s.blink_count_;
    if (recorder != nullptr && onset >= recorder->start && onset < recorder->end) {
      if (recorder->count < recorder->out.size()) recorder->out[recorder->count] = b;
      ++recorder->count;
    }
  }
};

// --- BlinkState ----------------------------------------------------------------

void BlinkState::Reseed(std::uint64_t seed) {
  rng_.Seed(seed);
  blink_count_ = 0;
  current_ = BlinkEvent{};
  ForgetTime();
}

void BlinkState::ForgetTime() {
  has_time_ = false;
  time_ = 0.0;
  phase_ = Phase::kOpen;
  gap_ = 0.0;
  gap_elapsed_ = 0.0;
  double_pending_ = false;
  double_onset_ = 0.0;
}

// --- BlinkJob ------------------------------------------------------------------

BlinkError BlinkJob::Validate() const {
  if (params == nullptr) return BlinkError::kNoParams;
  if (state == nullptr) return BlinkError::kNoState;
  if (out_left == nullptr || out_right == nullptr) return BlinkError::kNoOutput;
  if (!std::isfinite(time.count())) return BlinkError::kNonFiniteTime;
  if (!params->Validate()) return BlinkError::kInvalidParams;
  if (state->has_time() && time.count() < state->time()) return BlinkError::kTimeWentBackwards;
  return BlinkError::kNone;
}

BlinkError BlinkJob::Run() const {
  if (const BlinkError error = Validate(); error != BlinkError::kNone) return error;
  Derived derived;
  ComputeDerived(*params, &derived);  // cannot fail: Validate checked it
  if (!state->has_time()) {
    BlinkEngine::Begin(*state, *params, derived, time.count());
  } else {
    BlinkEngine::Step(*state, *params, derived, time.count(), talking, at_pause, nullptr);
  }
  BlinkEngine::Evaluate(*state, time.count(), out_left, out_right);
  return BlinkError::kNone;
}

// --- SimulateBlinks -----------------------------------------------------------------

BlinkError SimulateBlinks(const BlinkParams& params, std::uint64_t seed, double start, double end,
                          std::span<const BlinkActivity> activity, std::span<BlinkEvent> out,
                          std::size_t* count) {
  if (count == nullptr) return BlinkError::kNoOutput;
  *count = 0;
  if (!params.Validate()) return BlinkError::kInvalidParams;
  if (!std::isfinite(start) || !std::isfinite(end) || end < start) {
    return BlinkError::kInvalidInterval;
  }
  for (std::size_t i = 0; i < activity.size(); ++i) {
    const BlinkActivity& a = activity[i];
    if (!std::isfinite(a.start) || !std::isfinite(a.end) || a.end < a.start ||
        (i > 0 && a.start < activity[i - 1].end)) {
      return BlinkError::kInvalidInterval;
    }
  }

  Derived derived;
  ComputeDerived(params, &derived);
  BlinkState state(seed);
  BlinkEngine::Begin(state, params, derived, start);
  BlinkRecorder recorder{out, start, end, 0};
  std::size_t next = 0;  // first segment that has not ended yet
  double t = start;
  while (t < end) {
    while (next < activity.size() && activity[next].end <= t) ++next;
    const bool inside = next < activity.size() && activity[next].start <= t;
    const double boundary = inside ? activity[next].end
                            : next < activity.size() ? activity[next].start
                                                     : std::numeric_limits<double>::infinity();
    const double t_next = std::min({t + kSimulationStep, boundary, end});
    const bool talking = inside && activity[next].talking;
    const bool at_pause = inside && activity[next].at_pause;
    BlinkEngine::Step(state, params, derived, t_next, talking, at_pause, &recorder);
    t = t_next;
  }
  *count = recorder.count;
  return BlinkError::kNone;
}

}  // namespace facerig
