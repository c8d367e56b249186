#include "facerig/runtime/audio_clock.h"

#include <algorithm>
#include <cmath>

#include "finite_range.h"

namespace facerig {

namespace {

// Bounds for the measured callback period: a device that skipped a second
// must not let the clock run a second past its last report.
constexpr double kMinPeriodSeconds = 0.001;
constexpr double kMaxPeriodSeconds = 0.125;
// The period and lateness estimates follow the largest recent value
// (variable callback sizes, scheduling delays) and forget it over ~50
// reports, about a second.
constexpr double kDecay = 0.98;
// A read that collides with this many writes in a row uses the previous
// report; a collision needs the audio thread preempted mid-write.
constexpr int kMaxReadAttempts = 64;
// Share of a later-than-anchor report's excess taken into the anchor per
// report: follows clock drift of ~1e-3 with well under 1 ms of lag.
constexpr double kOffsetCreep = 0.02;

}  // namespace

bool AudioClockParams::Validate() const {
  return sample_rate >= 1000 && sample_rate <= 768000 &&
         InRange(output_latency_seconds, 0.0, 2.0) &&
         InRange(default_period_seconds, kMinPeriodSeconds, kMaxPeriodSeconds) &&
         InRange(smoothing_time_constant, 1e-3, 10.0) && InRange(max_slew, 1e-3, 0.5) &&
         InRange(resync_threshold_seconds, 0.01, 60.0);
}

const char* ToString(AudioClockStatus status) {
  switch (status) {
    case AudioClockStatus::kStopped: return "stopped";
    case AudioClockStatus::kWaitingForDevice: return "waiting for the audio device";
    case AudioClockStatus::kRunning: return "running";
    case AudioClockStatus::kDeviceStalled: return "audio device stalled";
    case AudioClockStatus::kSilent: return "silent (wall clock)";
  }
  return "unknown";
}

// --- audio thread ---------------------------------------------------------------

void AudioClock::OnDeviceProgress(std::int64_t samples_consumed, double wall_seconds) {
  if (samples_consumed < 0 || !std::isfinite(wall_seconds)) return;
  Writer& w = writer_;
  bool stalled = false;
  if (w.has_last) {
    if (samples_consumed < w.last_samples) {
      ++w.epoch;
    } else if (samples_consumed == w.last_samples) {
      stalled = true;
    } else {
      const auto delta = static_cast<double>(samples_consumed - w.last_samples);
      w.period_samples = std::max(delta, kDecay * w.period_samples + (1.0 - kDecay) * delta);
    }
  }
  w.has_last = true;
  w.last_samples = samples_consumed;
  ++w.count;

  // Seqlock write (Boehm 2012, "Can seqlocks get along with programming
  // language memory models?"): odd sequence, release fence, relaxed field
  // stores, even sequence with release.
  const std::uint64_t sequence = shared_.sequence.load(std::memory_order_relaxed);
  shared_.sequence.store(sequence + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  shared_.samples.store(samples_consumed, std::memory_order_relaxed);
  shared_.wall.store(wall_seconds, std::memory_order_relaxed);
  shared_.period_samples.store(w.period_samples, std::memory_order_relaxed);
  shared_.epoch_and_stalled.store((static_cast<std::uint64_t>(w.epoch) << 1u) | (stalled ? 1u : 0u),
                                  std::memory_order_relaxed);
  shared_.count.store(w.count, std::memory_order_relaxed);
  shared_.sequence.store(sequence + 2, std::memory_order_release);
}

// --- any thread -------------------------------------------------------------------

bool AudioClock::TryReadReport(AudioDeviceReport* report) const {
  for (int attempt = 0; attempt < kMaxReadAttempts; ++attempt) {
    const std::uint64_t before = shared_.sequence.load(std::memory_order_acquire);
    if ((before & 1u) != 0) continue;
    AudioDeviceReport r;
    r.samples_consumed = shared_.samples.load(std::memory_order_relaxed);
    r.wall_seconds = shared_.wall.load(std::memory_order_relaxed);
    r.period_samples = shared_.period_samples.load(std::memory_order_relaxed);
    const std::uint64_t epoch_and_stalled = shared_.epoch_and_stalled.load(std::memory_order_relaxed);
    r.count = shared_.count.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (shared_.sequence.load(std::memory_order_relaxed) != before) continue;
    r.epoch = static_cast<std::uint32_t>(epoch_and_stalled >> 1u);
    r.stalled = (epoch_and_stalled & 1u) != 0;
    *report = r;
    return true;
  }
  return false;
}

AudioDeviceReport AudioClock::LatestReport() const {
  AudioDeviceReport report;
  TryReadReport(&report);  // on failure: the empty report (count 0)
  return report;
}

// --- control / render thread -------------------------------------------------------------

bool AudioClock::Configure(const AudioClockParams& params) {
  if (!params.Validate()) return false;
  params_ = params;
  return true;
}

double AudioClock::Restart(double wall_seconds, Mode mode, AudioClockStatus status) {
  if (!std::isfinite(wall_seconds)) wall_seconds = value_wall_;
  mode_ = mode;
  status_ = status;
  base_ = value_;
  value_wall_ = wall_seconds;
  return wall_seconds;
}

void AudioClock::Start(double wall_seconds, std::int64_t origin_samples) {
  wall_seconds = Restart(wall_seconds, Mode::kDevice, AudioClockStatus::kWaitingForDevice);
  estimate_ = value_;
  last_report_time_ = base_;
  synced_ = false;
  has_offset_ = false;
  AudioDeviceReport report;
  if (TryReadReport(&report)) cached_report_ = report;
  const double rate = params_.sample_rate;
  epoch_seen_ = cached_report_.epoch;
  if (origin_samples != kOriginAtCurrentPosition) {
    origin_pending_ = false;
    origin_seconds_ = static_cast<double>(origin_samples) / rate;
  } else if (cached_report_.count > 0) {
    // Where the device is now: the last report plus the time since, within a period.
    const double since = cached_report_.stalled
                             ? 0.0
                             : std::clamp(wall_seconds - cached_report_.wall_seconds, 0.0,
                                          PeriodSeconds(cached_report_));
    origin_pending_ = false;
    origin_seconds_ = static_cast<double>(cached_report_.samples_consumed) / rate + since;
  } else {
    origin_pending_ = true;
  }
}

void AudioClock::StartSilent(double wall_seconds) {
  silent_start_wall_ = Restart(wall_seconds, Mode::kSilent, AudioClockStatus::kSilent);
}

void AudioClock::Stop(double wall_seconds) {
  Now(wall_seconds);
  mode_ = Mode::kStopped;
  status_ = AudioClockStatus::kStopped;
}

void AudioClock::Reset() {
  mode_ = Mode::kStopped;
  status_ = AudioClockStatus::kStopped;
  value_ = 0.0;
  base_ = 0.0;
  estimate_ = 0.0;
  origin_pending_ = false;
  last_report_time_ = 0.0;
}

double AudioClock::Now(double wall_seconds) {
  if (!std::isfinite(wall_seconds)) return value_;
  double next = value_;
  switch (mode_) {
    case Mode::kStopped:
      status_ = AudioClockStatus::kStopped;
      break;
    case Mode::kSilent:
      status_ = AudioClockStatus::kSilent;
      next = base_ + std::max(0.0, wall_seconds - silent_start_wall_);
      break;
    case Mode::kDevice:
      next = DeviceNow(wall_seconds);
      break;
  }
  value_ = std::max(value_, next);  // monotonic whatever happened
  value_wall_ = std::max(value_wall_, wall_seconds);
  return value_;
}

double AudioClock::PeriodSeconds(const AudioDeviceReport& report) const {
  const double period = report.period_samples > 0.0 ? report.period_samples / params_.sample_rate
                                                    : params_.default_period_seconds;
  return std::clamp(period, kMinPeriodSeconds, kMaxPeriodSeconds);
}

double AudioClock::DeviceNow(double wall_seconds) {
  AudioDeviceReport report;
  if (TryReadReport(&report)) cached_report_ = report;
  const AudioDeviceReport& r = cached_report_;
  if (r.count == 0) {
    status_ = AudioClockStatus::kWaitingForDevice;
    estimate_ = value_;
    return value_;
  }
  const double latency = params_.output_latency_seconds;
  const double consumed = static_cast<double>(r.samples_consumed) / params_.sample_rate;
  if (origin_pending_) {
    origin_pending_ = false;
    origin_seconds_ = consumed;
    epoch_seen_ = r.epoch;
  }
  if (r.epoch != epoch_seen_) {
    // The device counter restarted from 0 (a new device): assume its audio
    // follows the old device's without a gap, which played on for at most
    // a period after its last report.
    epoch_seen_ = r.epoch;
    double continued = last_report_time_ + PeriodSeconds(r) + consumed;
    if (has_offset_) continued = std::min(continued, r.wall_seconds - offset_);
    continued = std::max(continued, last_report_time_);
    origin_seconds_ = consumed + base_ - latency - continued;
  }
  // Animation time of the report's position (may be < base_ before the
  // origin or within the latency: the clock then holds at base_).
  const double report_time = base_ + (consumed - origin_seconds_) - latency;
  last_report_time_ = report_time;
  const double period = PeriodSeconds(r);

  // Callbacks run late, never early, by a varying delay, so the earliest
  // report (smallest wall - position) is the best anchor of the line
  // position = wall - offset. The offset follows new minima at once and
  // creeps up slowly (audio and wall clocks drift apart); a report later
  // than a whole period means the device paused or underran: re-anchor.
  if (r.count != last_report_count_) {
    last_report_count_ = r.count;
    if (!r.stalled) {
      const double offset = r.wall_seconds - report_time;
      if (!has_offset_ || offset - offset_ > period) {
        offset_ = offset;
        has_offset_ = true;
      } else if (offset < offset_) {
        offset_ = offset;
      } else {
        offset_ += kOffsetCreep * (offset - offset_);
      }
      lateness_ = std::min(std::max(offset - offset_, kDecay * lateness_), period);
    }
  }
  const double since_report = wall_seconds - r.wall_seconds;
  status_ = r.stalled || since_report > 2.0 * period ? AudioClockStatus::kDeviceStalled
                                                     : AudioClockStatus::kRunning;
  // Never more than a period (plus the callbacks' observed lateness) past
  // the last report; a device that reported no progress is where it said.
  const double ceiling = report_time + (r.stalled ? 0.0 : period + lateness_);
  const double target = std::min(has_offset_ ? wall_seconds - offset_ : report_time, ceiling);

  if (!synced_) {
    // The first report after Start: begin where the device is (a step of at
    // most one period from the start value, unless the origin is far back).
    synced_ = true;
    if (target - value_ > params_.resync_threshold_seconds) ++resync_count_;
    estimate_ = target;
    return target;
  }
  // The estimate runs at the nominal rate and corrects towards the target
  // at a bounded rate: no visible jumps, report jitter averaged out. It may
  // sit below the output (before the origin, after a ceiling hold); the
  // output then holds until it catches up.
  const double dt = std::max(0.0, wall_seconds - value_wall_);
  const double predicted = estimate_ + dt;
  const double error = target - predicted;
  if (error > params_.resync_threshold_seconds) {
    ++resync_count_;
    estimate_ = target;
    return target;
  }
  const double max_correction = params_.max_slew * dt;
  const double correction = std::clamp(
      error * (1.0 - std::exp(-dt / params_.smoothing_time_constant)), -max_correction, max_correction);
  estimate_ = std::min(predicted + correction, ceiling);
  return estimate_;
}

}  // namespace facerig
