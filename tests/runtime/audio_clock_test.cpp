#include "facerig/runtime/audio_clock.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/behaviour/blink.h"  // Pcg32 for the jitter
#include "measure/allocation_counter.h"

using facerig::AudioClock;
using facerig::AudioClockParams;
using facerig::AudioClockStatus;

namespace {

constexpr double kFrame = 1.0 / 60.0;

// A simulated audio device: plays during `running` wall intervals (sorted),
// pulls blocks of `block_sizes` samples (cycled), and its callback reports
// each block's running total up to `jitter` seconds after the device
// actually reached it. Latency-free: consumed = audible.
struct SimulatedDevice {
  int rate = 48000;
  std::vector<std::pair<double, double>> running;
  std::vector<int> block_sizes = {1024};
  double jitter = 0.003;
  bool report_while_paused = false;  // callbacks with no progress during pauses
  std::uint64_t seed = 1;            // of the callback jitter

  // Seconds of audio played by wall time w.
  double Position(double w) const {
    double played = 0.0;
    for (const auto& [from, to] : running) played += std::clamp(w, from, to) - from;
    return played;
  }
  // The wall time at which the position reaches p (p must be reachable).
  double WallAt(double p) const {
    for (const auto& [from, to] : running) {
      if (p <= to - from) return from + p;
      p -= to - from;
    }
    return std::numeric_limits<double>::infinity();
  }

  struct Report {
    double wall;
    std::int64_t samples;
  };
  std::vector<Report> Reports(double until) const {
    facerig::Pcg32 rng(seed);
    std::vector<Report> reports;
    std::int64_t samples = 0;
    double last_wall = 0.0;
    for (std::size_t k = 0;; ++k) {
      samples += block_sizes[k % block_sizes.size()];
      const double nominal = WallAt(static_cast<double>(samples) / rate);
      if (report_while_paused) {
        // The callback keeps firing every block period while the device is paused.
        const double period = static_cast<double>(block_sizes[0]) / rate;
        for (double w = last_wall + period; w + period < nominal && w < until; w += period) {
          reports.push_back({w, samples - block_sizes[k % block_sizes.size()]});
          last_wall = w;
        }
      }
      const double wall = std::max(last_wall + 1e-6, nominal + jitter * rng.NextDouble());
      if (wall > until) break;
      reports.push_back({wall, samples});
      last_wall = wall;
    }
    return reports;
  }
};

struct Frame {
  double wall;
  double time;       // AudioClock::Now
  double expected;   // the device's true position
  AudioClockStatus status;
};

// Renders at ~60 fps (+-1 ms jitter) from `from` to `until`, delivering the
// device's reports from `from` on in wall-time order before each frame.
std::vector<Frame> Render(AudioClock& clock, const SimulatedDevice& device, double from, double until,
                          std::uint64_t seed = 2) {
  const std::vector<SimulatedDevice::Report> reports = device.Reports(until);
  facerig::Pcg32 rng(seed);
  std::vector<Frame> frames;
  std::size_t next_report = 0;
  while (next_report < reports.size() && reports[next_report].wall < from) ++next_report;
  for (double nominal = from; nominal < until; nominal += kFrame) {
    const double wall = nominal + 0.002 * (rng.NextDouble() - 0.5);
    while (next_report < reports.size() && reports[next_report].wall <= wall) {
      clock.OnDeviceProgress(reports[next_report].samples, reports[next_report].wall);
      ++next_report;
    }
    const double time = clock.Now(wall);
    frames.push_back({wall, time, device.Position(wall), clock.status()});
  }
  return frames;
}

// Monotonic, and no step longer than the frame interval (plus the slew),
// but for the start on the first device report: at most one callback period.
void CheckSmooth(const std::vector<Frame>& frames, double max_slew, double period = 2048.0 / 44100.0) {
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double step = frames[i].time - frames[i - 1].time;
    const double interval = frames[i].wall - frames[i - 1].wall;
    INFO("frame " << i << " at wall " << frames[i].wall << ": step " << step << " over " << interval);
    REQUIRE(step >= 0.0);
    if (frames[i - 1].status == AudioClockStatus::kWaitingForDevice) {
      REQUIRE(step <= interval + period + 0.005);
    } else {
      REQUIRE(step <= interval * (1.0 + max_slew) + 1e-9);
    }
  }
}

double MaxError(const std::vector<Frame>& frames, double from, double until, double offset = 0.0) {
  double worst = 0.0;
  for (const Frame& f : frames) {
    if (f.wall >= from && f.wall <= until) {
      worst = std::max(worst, std::abs(f.time - (f.expected - offset)));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("AudioClock follows a jittery device within a few ms", "[audio_clock]") {
  struct Case {
    const char* name;
    int rate;
    std::vector<int> blocks;
    double jitter;
  };
  const std::vector<Case> cases = {{"48 kHz, 1024-sample callbacks, 3 ms jitter", 48000, {1024}, 0.003},
                                   {"44.1 kHz, 512-2048-sample callbacks, 4 ms jitter", 44100,
                                    {512, 2048, 1024, 2048, 512, 1024, 1024}, 0.004},
                                   {"22.05 kHz, 2048-sample callbacks, 5 ms jitter", 22050, {2048}, 0.005}};
  for (const Case& c : cases) {
    SimulatedDevice device;
    device.rate = c.rate;
    device.block_sizes = c.blocks;
    device.jitter = c.jitter;
    device.running = {{0.05, 1e9}};
    AudioClock clock;
    AudioClockParams params;
    params.sample_rate = c.rate;
    REQUIRE(clock.Configure(params));
    clock.Start(0.0, /*origin_samples=*/0);
    const std::vector<Frame> frames = Render(clock, device, 0.0, 60.0);
    INFO(c.name);
    const double max_period =
        *std::max_element(c.blocks.begin(), c.blocks.end()) / static_cast<double>(c.rate);
    CheckSmooth(frames, params.max_slew, max_period);
    // Before the device starts, the clock waits at 0.
    CHECK(frames[1].time == 0.0);
    CHECK(frames[1].status == AudioClockStatus::kWaitingForDevice);
    const double steady = MaxError(frames, 0.3, 60.0);
    const double all = MaxError(frames, 0.0, 60.0);
    std::printf("AudioClock, %s: max |clock - playback| %.2f ms after 0.3 s, %.1f ms overall\n",
                c.name, 1000.0 * steady, 1000.0 * all);
    CHECK(steady <= 0.006);
    // Start-up: the device plays its first block before the first report.
    CHECK(all <= max_period + c.jitter + 0.005);
    CHECK(frames.back().status == AudioClockStatus::kRunning);
  }
}

TEST_CASE("AudioClock holds while the device pauses and resumes smoothly", "[audio_clock]") {
  for (bool report_while_paused : {false, true}) {
    SimulatedDevice device;
    device.running = {{0.05, 2.0}, {3.5, 1e9}};
    device.report_while_paused = report_while_paused;
    AudioClock clock;
    const double period = 1024.0 / 48000.0;
    clock.Start(0.0, 0);
    const std::vector<Frame> frames = Render(clock, device, 0.0, 8.0);
    INFO("reports while paused: " << report_while_paused);
    CheckSmooth(frames, clock.params().max_slew);
    const double paused_at = device.Position(2.0);
    double held = -1.0;
    for (const Frame& f : frames) {
      if (f.wall > 2.0 && f.wall < 3.5) {
        // Never more than one callback period past the device.
        REQUIRE(f.time <= paused_at + period + 1e-9);
      }
      if (f.wall > 2.0 + 2 * period + 0.01 && f.wall < 3.5) {
        if (held < 0.0) held = f.time;
        REQUIRE(f.time == held);  // stopped
        REQUIRE(f.status == AudioClockStatus::kDeviceStalled);
      }
    }
    CHECK(held >= paused_at - 0.006);
    CHECK(MaxError(frames, 0.3, 2.0) <= 0.006);
    CHECK(MaxError(frames, 2.0, 8.0) <= period + 0.006);  // around the pause
    CHECK(MaxError(frames, 4.5, 8.0) <= 0.006);           // caught up
  }
}

TEST_CASE("AudioClock start, stop, origin, latency and reset", "[audio_clock]") {
  SimulatedDevice device;
  device.running = {{0.0, 1e9}};
  device.jitter = 0.002;

  SECTION("start at the device's current position, stop, resume") {
    AudioClock clock;
    // The device has been playing for a second before the line starts.
    std::vector<Frame> warmup = Render(clock, device, 0.0, 1.0);
    CHECK(warmup.back().time == 0.0);
    CHECK(clock.status() == AudioClockStatus::kStopped);
    clock.Start(1.0);
    std::vector<Frame> frames = Render(clock, device, 1.0, 2.0, 3);
    CheckSmooth(frames, clock.params().max_slew);
    CHECK(MaxError(frames, 1.3, 2.0, /*offset=*/1.0) <= 0.006);
    clock.Stop(2.0);
    const double stopped = clock.Now(2.0);
    CHECK(stopped == Approx(1.0).margin(0.006));
    frames = Render(clock, device, 2.0, 3.0, 4);
    for (const Frame& f : frames) REQUIRE(f.time == stopped);
    CHECK(clock.status() == AudioClockStatus::kStopped);
    clock.Start(3.0);  // resumes from `stopped`, counting from the device's position now
    frames = Render(clock, device, 3.0, 4.0, 5);
    CheckSmooth(frames, clock.params().max_slew);
    CHECK(frames.front().time >= stopped);
    CHECK(MaxError(frames, 3.3, 4.0, /*offset=*/3.0 - stopped) <= 0.006);
    clock.Reset();
    CHECK(clock.Now(4.0) == 0.0);
    CHECK(clock.status() == AudioClockStatus::kStopped);
  }

  SECTION("explicit origin: time 0 is a given device sample") {
    AudioClock clock;
    clock.Start(0.0, /*origin_samples=*/48000);  // the line starts 1 s into the stream
    const std::vector<Frame> frames = Render(clock, device, 0.0, 3.0);
    CheckSmooth(frames, clock.params().max_slew);
    for (const Frame& f : frames) {
      if (f.wall < 0.99) REQUIRE(f.time == 0.0);
    }
    CHECK(MaxError(frames, 1.3, 3.0, /*offset=*/1.0) <= 0.006);
  }

  SECTION("output latency: the clock reports the audible position") {
    AudioClock clock;
    AudioClockParams params;
    params.output_latency_seconds = 0.05;
    REQUIRE(clock.Configure(params));
    clock.Start(0.0, 0);
    const std::vector<Frame> frames = Render(clock, device, 0.0, 3.0);
    CheckSmooth(frames, params.max_slew);
    for (const Frame& f : frames) {
      if (f.wall < 0.045) REQUIRE(f.time == 0.0);
    }
    CHECK(MaxError(frames, 0.4, 3.0, /*offset=*/0.05) <= 0.006);
  }

  SECTION("a device far ahead (seek) makes one forward jump") {
    AudioClock clock;
    Render(clock, device, 0.0, 5.0);
    clock.Start(5.0, /*origin_samples=*/0);  // the line started with the stream, 5 s ago
    const std::vector<Frame> frames = Render(clock, device, 5.0, 6.0, 6);
    CHECK(clock.resync_count() == 1);
    CHECK(frames.front().time == Approx(5.0).margin(0.025));
    CHECK(MaxError(frames, 5.3, 6.0) <= 0.006);
  }
}

TEST_CASE("AudioClock jumps forward once when the device skips ahead", "[audio_clock]") {
  AudioClock clock;
  clock.Start(0.0, 0);
  std::vector<Frame> frames;
  std::int64_t skip = 0;
  double next_report = 1024.0 / 48000.0;
  for (double wall = 0.0; wall < 3.0; wall += kFrame) {
    for (; next_report <= wall; next_report += 1024.0 / 48000.0) {
      if (next_report >= 1.0) skip = 2 * 48000;  // 2 s of the stream skipped at 1 s
      clock.OnDeviceProgress(std::llround(next_report * 48000.0) + skip, next_report);
    }
    frames.push_back({wall, clock.Now(wall), wall + (wall >= 1.0 + kFrame ? 2.0 : 0.0),
                      clock.status()});
  }
  CHECK(clock.resync_count() == 1);
  CHECK(MaxError(frames, 0.3, 0.98) <= 0.002);
  CHECK(MaxError(frames, 1.1, 3.0) <= 0.002);
}

TEST_CASE("AudioClock continues through a device restart", "[audio_clock]") {
  // Device A plays 0-2 s; a new device (counter from 0) plays from 2 s on.
  SimulatedDevice a, b;
  a.running = {{0.0, 2.0}};
  b.running = {{2.0, 1e9}};
  AudioClock clock;
  clock.Start(0.0, 0);
  std::vector<Frame> frames;
  const std::vector<SimulatedDevice::Report> reports_a = a.Reports(2.0);
  b.seed = 9;
  const std::vector<SimulatedDevice::Report> reports_b = b.Reports(5.0);
  std::size_t ia = 0, ib = 0;
  for (double wall = 0.0; wall < 5.0; wall += kFrame) {
    while (ia < reports_a.size() && reports_a[ia].wall <= wall) {
      clock.OnDeviceProgress(reports_a[ia].samples, reports_a[ia].wall);
      ++ia;
    }
    while (ib < reports_b.size() && reports_b[ib].wall <= wall) {
      clock.OnDeviceProgress(reports_b[ib].samples, reports_b[ib].wall);
      ++ib;
    }
    frames.push_back({wall, clock.Now(wall), wall, clock.status()});
  }
  CHECK(clock.LatestReport().epoch == 1);
  CheckSmooth(frames, clock.params().max_slew);
  // Audio played continuously, so the clock stays near wall time throughout.
  CHECK(MaxError(frames, 0.3, 5.0) <= 0.03);
  CHECK(MaxError(frames, 3.5, 5.0) <= 0.006);
}

TEST_CASE("AudioClock silent mode runs from wall time", "[audio_clock]") {
  AudioClock clock;
  clock.StartSilent(10.0);
  CHECK(clock.silent());
  CHECK(clock.status() == AudioClockStatus::kSilent);
  CHECK(clock.Now(10.5) == Approx(0.5));
  CHECK(clock.Now(11.0) == Approx(1.0));
  // Device reports do not matter in silent mode.
  clock.OnDeviceProgress(480000, 11.0);
  CHECK(clock.Now(11.25) == Approx(1.25));
  clock.Stop(12.0);
  CHECK_FALSE(clock.silent());
  CHECK(clock.Now(20.0) == Approx(2.0));
  clock.StartSilent(30.0);
  CHECK(clock.Now(30.25) == Approx(2.25));
  clock.Reset();
  CHECK(clock.Now(31.0) == 0.0);
}

TEST_CASE("AudioClock rejects bad input safely", "[audio_clock]") {
  AudioClock clock;
  AudioClockParams bad;
  bad.sample_rate = 0;
  CHECK_FALSE(clock.Configure(bad));
  bad = AudioClockParams{};
  bad.max_slew = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(clock.Configure(bad));
  CHECK(clock.params().sample_rate == 48000);  // unchanged

  clock.OnDeviceProgress(-5, 1.0);
  clock.OnDeviceProgress(100, std::numeric_limits<double>::quiet_NaN());
  CHECK(clock.LatestReport().count == 0);

  clock.Start(0.0, 0);
  for (int i = 1; i <= 100; ++i) clock.OnDeviceProgress(i * 480, i * 0.01);
  const double t = clock.Now(1.0);
  CHECK(t == Approx(1.0).margin(0.02));
  CHECK(clock.Now(std::numeric_limits<double>::quiet_NaN()) == t);
  CHECK(clock.Now(-std::numeric_limits<double>::infinity()) == t);
  CHECK(clock.Now(0.5) >= t);  // a backwards wall time never moves the clock back
  clock.Start(std::numeric_limits<double>::quiet_NaN());
  CHECK(clock.Now(1.01) >= t);
}

TEST_CASE("AudioClock does not allocate", "[audio_clock]") {
  AudioClock clock;
  clock.Start(0.0, 0);
  facerig::test::AllocationCounter counter;
  double sum = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const double wall = i * 0.005;
    if (i % 4 == 0) clock.OnDeviceProgress(static_cast<std::int64_t>(i) * 240, wall);
    sum += clock.Now(wall);
    sum += static_cast<double>(clock.LatestReport().count);
  }
  clock.Stop(50.0);
  clock.StartSilent(50.0);
  sum += clock.Now(51.0);
  CHECK(counter.count() == 0);
  CHECK(sum > 0.0);
}

TEST_CASE("AudioClock hand-over between an audio and a render thread", "[audio_clock]") {
  // The writer's wall time is a function of the count, so a torn read shows.
  AudioClock clock;
  clock.Start(0.0, 0);
  std::atomic<bool> stop{false};
  std::thread audio([&] {
    std::int64_t samples = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      samples += 64;
      clock.OnDeviceProgress(samples, static_cast<double>(samples) / 48000.0);
    }
  });
  bool consistent = true, monotonic = true;
  std::uint64_t last_count = 0;
  double last_time = 0.0;
  const auto start = std::chrono::steady_clock::now();
  long reads = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(200)) {
    const facerig::AudioDeviceReport r = clock.LatestReport();
    if (r.count > 0) {
      consistent = consistent && r.wall_seconds == static_cast<double>(r.samples_consumed) / 48000.0 &&
                   r.count >= last_count;
      last_count = r.count;
    }
    const double time = clock.Now(static_cast<double>(reads) * 1e-4);
    monotonic = monotonic && time >= last_time;
    last_time = time;
    ++reads;
  }
  stop = true;
  audio.join();
  CHECK(consistent);
  CHECK(monotonic);
  CHECK(last_count > 0);
}
