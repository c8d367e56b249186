// Spontaneous blinks from published statistics, as eyelid closure weights for
// eyeBlink_L / eyeBlink_R (0 = open, 1 = closed).
//
// The model (all numbers are BlinkParams defaults):
// - Rate: 17 blinks/min at rest, 26/min while talking (Bentivoglio et al.
//   1997, "Analysis of blink rate patterns in normal subjects", Mov. Disord.
//   12(6): 17.0/min at rest, 26.0/min in conversation). Every closure counts,
//   the second of a double blink included, so the long-run mean interval
//   between blink onsets is 60 / rate seconds.
// - Intervals: renewal process. After a blink the eyes stay open for
//   min_gap + LogNormal(mu, sigma) seconds of "blink clock" time: right-
//   skewed with a long tail, as inter-blink intervals are usually described
//   (since Ponder & Kennedy 1927). A log-normal gives that shape from two
//   intuitive numbers: the mean, derived from the rate so that intervals
//   average 60 / rate, and sigma = 0.75 (coefficient of variation ~0.9 for
//   the log-normal part); min_gap (0.25 s) is the refractory time after a
//   blink.
// - The blink clock runs at speed 1 at rest and faster while talking (26/17 x,
//   corrected for durations); during a signalled speech pause it runs
//   pause_hazard_boost (4) times faster than during speech. The speech-time
//   speed is normalised by a running estimate of the share of eyes-open
//   talking time spent in pauses, so the talking rate stays ~26/min however
//   often the caller signals pauses: pauses attract blinks without adding
//   any. Draws happen per blink and onsets are solved exactly inside a
//   frame, so the blink sequence hardly depends on the frame rate.
// - Shape: whole blink 150-400 ms, triangular distribution (mode 220 ms,
//   median ~250 ms, right-skewed like measured durations); closing takes
//   ~0.4 x the opening time (ratio uniform in [0.33, 0.47]) with a short hold
//   at full closure. Each phase follows a smoothstep, so the weight and its
//   derivative are continuous.
// - Double blinks: 4% of blinks are followed 50-200 ms after they end by a
//   second one.
// - Eyes: both blink together; one eye starts up to 6 ms later (which one is
//   random per blink) and each eye's peak closure differs by up to 0.05.
//
// Determinism: the generator is a PCG32 of our own; uniforms are built from
// its integer output, normals by Marsaglia's polar method. Only std::log,
// std::exp and std::sqrt touch the draws, so a seed gives the same blinks on
// every platform up to last-ulp differences between libm implementations
// (~1e-15 s on event times; the yes/no draws compare exact uniforms).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "facerig/runtime/seconds.h"

namespace facerig {

// PCG32 (O'Neill 2014, XSH-RR variant): small, fast, and its output is fully
// specified, unlike the <random> distributions.
class Pcg32 {
 public:
  explicit Pcg32(std::uint64_t seed = 0, std::uint64_t stream = 0x14057b7ef767814fULL) {
    Seed(seed, stream);
  }
  void Seed(std::uint64_t seed, std::uint64_t stream = 0x14057b7ef767814fULL);
  std::uint32_t Next();
  // Uniform in [0, 1) with 53 random bits.
  double NextDouble();
  // Standard normal (Marsaglia polar method).
  double NextNormal();

 private:
  std::uint64_t state_ = 0;
  std::uint64_t increment_ = 1;
};

enum class BlinkError : std::uint8_t {
  kNone,
  kNoParams,
  kInvalidParams,      // see BlinkParams::Validate
  kNoState,
  kNoOutput,           // out_left or out_right is null
  kNonFiniteTime,
  kTimeWentBackwards,  // time < the previous Run's time on this state
  kInvalidInterval,    // SimulateBlinks: end < start, or bad activity segments
};

const char* ToString(BlinkError error);

// Times in seconds, rates in blinks per minute, weights in [0, 1].
struct BlinkParams {
  double rest_rate_per_min = 17.0;
  double talking_rate_per_min = 26.0;

  // Eyes-open time between blinks, in blink-clock seconds:
  // min_gap_seconds + LogNormal(mu, gap_log_sigma), mu derived from the rates.
  double min_gap_seconds = 0.25;
  double gap_log_sigma = 0.75;

  // Whole blink (close + hold + open) of one eye: triangular distribution.
  double min_duration_seconds = 0.15;
  double mode_duration_seconds = 0.22;
  double max_duration_seconds = 0.40;
  // Closing time / opening time, uniform in [min, max] per blink.
  double min_close_open_ratio = 0.33;
  double max_close_open_ratio = 0.47;
  // Share of the blink held at full closure, between closing and opening.
  double hold_fraction = 0.05;
  // Peak closure, uniform in [min_peak, 1] per blink; each eye then loses up
  // to max_eye_peak_difference of it independently.
  float min_peak = 0.92f;
  float max_eye_peak_difference = 0.05f;
  // One eye starts up to this much after the other (uniform, random side).
  double max_eye_offset_seconds = 0.006;

  // Chance that a blink (not itself a second one) is followed by another
  // min..max double-blink gap after it ends.
  double double_blink_probability = 0.04;
  double min_double_gap_seconds = 0.05;
  double max_double_gap_seconds = 0.20;

  // While talking and at a pause, the blink clock runs this much faster than
  // during speech (1 = pauses do not matter).
  double pause_hazard_boost = 4.0;
  // Share of talking time spent in pauses, assumed until measured, and the
  // time constant of its running estimate.
  double prior_pause_fraction = 0.15;
  double pause_fraction_time_constant = 20.0;

  // A forward step longer than this (a hitch, a seek, a suspended app) does
  // not replay the missed blinks: any blink in progress ends and the next
  // interval starts afresh. At most 1 s.
  double max_time_step_seconds = 0.5;

  // True when every field is finite and in range and the rates leave room
  // for the blinks themselves (e.g. 120/min with 400 ms blinks does not).
  bool Validate() const;
};

// One blink of both eyes. The left eye starts at start + max(0, -eye_offset),
// the right eye at start + max(0, eye_offset); each eye's closure lasts
// `duration` = close + hold + open.
struct BlinkEvent {
  double start = 0.0;
  double duration = 0.0;
  double close_duration = 0.0;
  double hold_duration = 0.0;
  double open_duration = 0.0;
  double eye_offset = 0.0;  // right onset - left onset
  float peak_left = 1.0f;
  float peak_right = 1.0f;
  bool second_of_double = false;

  double end() const { return start + (eye_offset < 0.0 ? -eye_offset : eye_offset) + duration; }
};

// Closure of one eye `t` seconds after that eye's onset, for a blink with
// the given phases and peak: 0 outside [0, close + hold + open).
float BlinkClosure(const BlinkEvent& blink, double t, float peak);

class BlinkEngine;  // blink.cpp

// The per-character context, carried from frame to frame: RNG, blink clock,
// current blink. Sized once (no heap memory); copyable (a copy continues the
// same random sequence).
class BlinkState {
 public:
  explicit BlinkState(std::uint64_t seed = 0) { Reseed(seed); }

  // Starts over: new random sequence, no time origin, eyes open.
  void Reseed(std::uint64_t seed);
  // Keeps the random sequence but forgets the time origin: the next Run may
  // use any time (e.g. after the timeline restarted). Eyes open.
  void ForgetTime();

  // False until the first Run (and after Reseed / ForgetTime).
  bool has_time() const { return has_time_; }
  // The time of the previous Run; the next one must not be earlier.
  double time() const { return time_; }
  // Blinks started so far (each half of a double blink counts).
  std::uint64_t blink_count() const { return blink_count_; }
  // The most recent blink (valid when blink_count() > 0).
  const BlinkEvent& last_blink() const { return current_; }
  // Running estimate of the share of talking time spent at pauses.
  double pause_fraction() const { return pause_fraction_; }

 private:
  friend class BlinkEngine;
  enum class Phase : std::uint8_t { kOpen, kBlinking, kDoubleWait };

  Pcg32 rng_;
  bool has_time_ = false;
  double time_ = 0.0;             // time of the previous Run
  Phase phase_ = Phase::kOpen;
  double gap_ = 0.0;              // blink-clock seconds to wait in kOpen
  double gap_elapsed_ = 0.0;      // blink-clock seconds waited so far
  double double_onset_ = 0.0;     // kDoubleWait: when the second blink starts
  bool double_pending_ = false;   // current blink is followed by a second
  double double_gap_ = 0.0;
  double pause_fraction_ = 0.0;
  std::uint64_t blink_count_ = 0;
  BlinkEvent current_;
};

// Per-frame blink update. Run() allocates nothing, throws nothing, takes no
// lock. `talking` and `at_pause` describe the interval since the previous
// Run; `at_pause` (a silence or phrase boundary in speech, held for its
// duration) only counts while talking.
struct BlinkJob {
  const BlinkParams* params = nullptr;
  BlinkState* state = nullptr;
  Seconds time{0.0};  // finite, non-decreasing across Runs of one state
  bool talking = false;
  bool at_pause = false;
  float* out_left = nullptr;   // eyeBlink_L closure in [0, 1]
  float* out_right = nullptr;  // eyeBlink_R closure in [0, 1]

  // Checks the inputs without touching the state or outputs.
  BlinkError Validate() const;
  // Validates, advances the state to `time` and writes both closures. On
  // error the state and outputs are left untouched.
  BlinkError Run() const;
};

// A stretch of time with constant activity, for SimulateBlinks.
struct BlinkActivity {
  double start = 0.0;
  double end = 0.0;
  bool talking = false;
  bool at_pause = false;
};

// Pre-simulates the blinks of a fresh BlinkState(seed) over [start, end),
// stepping like a 60 fps BlinkJob, with `activity` (sorted, non-overlapping
// segments; time outside them is rest). Writes the first out.size() blinks
// that start in [start, end) to `out` and their total number to *count
// (which may exceed out.size()). Pure; allocates nothing.
BlinkError SimulateBlinks(const BlinkParams& params, std::uint64_t seed, double start, double end,
                          std::span<const BlinkActivity> activity, std::span<BlinkEvent> out,
                          std::size_t* count);

}  // namespace facerig
