// Animation time from the audio playback position.
//
// Lip sync is judged against the sound, so the animation clock follows the
// samples the audio device has consumed, not the wall clock: if the device
// starts late, stalls or drifts against the system clock, the face follows.
//
// Threads: the audio callback calls OnDeviceProgress(); one control/render
// thread calls everything else. The hand-over is a seqlock over atomics: the
// audio thread never waits, the render thread retries a bounded number of
// times and otherwise uses the previous report. No mutex, no allocation.
//
// Model and latency assumptions:
// - A report (samples_consumed, wall_seconds) says the device had pulled
//   that many samples (its running total since it was opened) by that wall
//   time. Reports are coarse (one per callback, 512-2048 samples) and come
//   late by a varying scheduling delay, never early. The device consumes at
//   the nominal rate, so position = wall - offset; the offset is anchored on
//   the least-late reports (a running minimum that creeps up slowly to follow
//   drift between the audio and wall clocks, re-anchored when a report is
//   more than a period late: pause, underrun). Jitter then costs well under
//   a millisecond instead of its mean.
// - Never more than one callback period past the last report (the period is
//   the recent largest gap between reports, plus the recent largest callback
//   delay, which a running device may also show), so a paused or stalled
//   device stops the clock within about a period; a report with no progress
//   stops it where the device is.
// - Consumed is not audible: pulled samples sit in the device buffer for
//   output_latency_seconds before they are heard (for SDL2 about one device
//   buffer, samples / rate, plus the driver's; WASAPI / CoreAudio / ALSA
//   report it). The clock gives the audible position, consumed - latency,
//   holding at the start value until it is reached. Display latency (a frame
//   shows ~1 vsync after it is rendered) is the caller's: pass
//   wall_seconds + display latency to Now().
// - Both threads give wall times from the same monotonic clock, in seconds
//   (e.g. std::chrono::steady_clock).
// - Smoothing: an estimate advances at the nominal rate and corrects towards
//   the device position by at most max_slew of the elapsed time; the output
//   is its running maximum, so it is monotonic and never jumps. Exceptions,
//   both forward: the first report after Start (the clock starts where the
//   device is: at most a period from the start value, unless the origin
//   given to Start is further back) and a device more than
//   resync_threshold_seconds ahead (a seek, a skip; counted in
//   resync_count()).
// - Silent mode (no audio device): runs from the wall clock; silent() says so.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>

namespace facerig {

struct AudioClockParams {
  int sample_rate = 48000;                   // Hz
  double output_latency_seconds = 0.0;       // consumed -> audible, see above
  double default_period_seconds = 0.1;       // assumed callback period until measured
  double smoothing_time_constant = 0.1;      // seconds to correct ~63% of an error
  double max_slew = 0.1;                     // |clock rate - 1| while correcting
  double resync_threshold_seconds = 0.5;     // behind by more: jump forward

  bool Validate() const;
};

enum class AudioClockStatus : std::uint8_t {
  kStopped,           // Now() returns the time where Stop() (or Reset()) left it
  kWaitingForDevice,  // started, no device report yet: holding
  kRunning,           // following the device
  kDeviceStalled,     // no progress for more than a period: holding
  kSilent,            // no device: wall-clock time
};

const char* ToString(AudioClockStatus status);

// The latest device report as the render thread sees it.
struct AudioDeviceReport {
  std::int64_t samples_consumed = 0;
  double wall_seconds = 0.0;
  double period_samples = 0.0;  // recent largest gap between reports, 0 until two reports
  std::uint32_t epoch = 0;      // +1 each time the device counter went backwards (restart)
  std::uint64_t count = 0;      // reports accepted so far (0: none yet)
  bool stalled = false;         // the latest report showed no progress
};

class AudioClock {
 public:
  // For Start(): the animation's time 0 (or where Stop left it) is the
  // device's position at the first report the clock sees after Start.
  static constexpr std::int64_t kOriginAtCurrentPosition = std::numeric_limits<std::int64_t>::min();

  AudioClock() = default;
  AudioClock(const AudioClock&) = delete;
  AudioClock& operator=(const AudioClock&) = delete;

  // --- audio thread -------------------------------------------------------
  // Lock-free and wait-free. Reports with a negative count or a non-finite
  // time are ignored. A count lower than the previous one is a device
  // restart: the clock continues from where it is, counting from the new
  // position.
  void OnDeviceProgress(std::int64_t samples_consumed, double wall_seconds);

  // --- control / render thread (one thread) ---------------------------------
  // Sets the params; false (and nothing changes) when they are invalid.
  bool Configure(const AudioClockParams& params);
  const AudioClockParams& params() const { return params_; }

  // Follows the device from here on. The clock continues from its current
  // value (0 after Reset); that value corresponds to device sample
  // `origin_samples` (e.g. the first sample of the line's audio in the
  // device's running count), by default to the device's current position.
  void Start(double wall_seconds, std::int64_t origin_samples = kOriginAtCurrentPosition);
  // Runs from the wall clock instead, continuing from the current value.
  void StartSilent(double wall_seconds);
  // Freezes the clock at Now(wall_seconds).
  void Stop(double wall_seconds);
  // Stopped at time 0.
  void Reset();

  // Animation time in seconds at this wall time: monotonic, smooth. A
  // non-finite wall time returns the previous value.
  double Now(double wall_seconds);

  AudioClockStatus status() const { return status_; }
  bool silent() const { return mode_ == Mode::kSilent; }
  // Forward jumps made because the device was far ahead (seek, skip).
  std::uint64_t resync_count() const { return resync_count_; }

  // The latest complete report (seqlock read; any thread).
  AudioDeviceReport LatestReport() const;

 private:
  enum class Mode : std::uint8_t { kStopped, kDevice, kSilent };
  bool TryReadReport(AudioDeviceReport* report) const;
  double PeriodSeconds(const AudioDeviceReport& report) const;
  double DeviceNow(double wall_seconds);
  // What Start and StartSilent share: the clock carries on from its value at
  // `wall_seconds` (the last wall time when not finite), which it returns.
  double Restart(double wall_seconds, Mode mode, AudioClockStatus status);

  static_assert(std::atomic<std::int64_t>::is_always_lock_free);
  static_assert(std::atomic<double>::is_always_lock_free);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

  // Written by the audio thread, read by the render thread. Own cache line,
  // so the render thread's fields do not bounce with it.
  struct alignas(64) Shared {
    std::atomic<std::uint64_t> sequence{0};  // odd while a report is written
    std::atomic<std::int64_t> samples{0};
    std::atomic<double> wall{0.0};
    std::atomic<double> period_samples{0.0};
    std::atomic<std::uint64_t> epoch_and_stalled{0};  // epoch << 1 | stalled
    std::atomic<std::uint64_t> count{0};
  };
  Shared shared_;

  // Audio thread only.
  struct alignas(64) Writer {
    bool has_last = false;
    std::int64_t last_samples = 0;
    double period_samples = 0.0;
    std::uint32_t epoch = 0;
    std::uint64_t count = 0;
  };
  Writer writer_;

  // Render thread only.
  AudioClockParams params_;
  Mode mode_ = Mode::kStopped;
  AudioClockStatus status_ = AudioClockStatus::kStopped;
  AudioDeviceReport cached_report_;  // fallback when a read keeps colliding
  double value_ = 0.0;               // last time returned (monotonic)
  double value_wall_ = 0.0;          // wall time of value_
  double estimate_ = 0.0;            // smoothed device time; value_ = max over time
  double base_ = 0.0;                // clock value at Start / StartSilent
  double silent_start_wall_ = 0.0;
  bool origin_pending_ = false;      // take the origin from the next report
  bool synced_ = false;              // a report was used since Start
  double origin_seconds_ = 0.0;      // device samples / rate that map to base_
  std::uint32_t epoch_seen_ = 0;
  double last_report_time_ = 0.0;    // animation time of the last report's position
  std::uint64_t last_report_count_ = 0;
  bool has_offset_ = false;
  double offset_ = 0.0;              // wall - animation time, anchored on the earliest reports
  double lateness_ = 0.0;            // recent largest report delay beyond the anchor
  std::uint64_t resync_count_ = 0;
};

}  // namespace facerig
