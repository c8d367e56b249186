// Per-frame CPU timing of the player, split by stage, with percentiles at the end.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace facerig::player {

enum class Stage : std::size_t {
  kUpdate,   // Character::Update + idle life (speech, emotions, blinks -> weights)
  kBlend,    // BlendJob: positions and recomputed normals, where they moved
  kUpload,   // glBufferSubData of positions + normals
  kDraw,     // GL draw submission (headless: + glFinish, so the GPU work is counted)
};
inline constexpr std::size_t kStageCount = 4;
const char* ToString(Stage stage);

struct FrameSample {
  std::array<double, kStageCount> ms{};  // milliseconds per stage
  double total_ms() const;
};

struct StageSummary {
  double p50 = 0.0, p95 = 0.0, p99 = 0.0, worst = 0.0, mean = 0.0;
};

struct TimingSummary {
  std::size_t frames = 0;
  std::array<StageSummary, kStageCount> stages{};
  StageSummary total;
  std::size_t worst_frame = 0;  // index of the frame with the largest total
};

// Collects one FrameSample per frame. The sample storage is reserved up front
// so recording a frame does not allocate until `reserve_frames` is exceeded.
class FrameTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit FrameTimer(std::size_t reserve_frames = 1 << 16);

  void BeginFrame();
  // Ends the stage that started at the previous Mark/BeginFrame.
  void Mark(Stage stage);
  void EndFrame();

  const std::vector<FrameSample>& samples() const { return samples_; }
  // The percentiles of the last `window` frames (all when 0): for the HUD.
  TimingSummary Summarize(std::size_t window = 0) const;

 private:
  std::vector<FrameSample> samples_;
  FrameSample current_;
  Clock::time_point last_;
};

// "frames 120  total p50 1.23 ms p95 ... worst 3.4 ms (frame 17)" and one line per stage.
std::string FormatSummary(const TimingSummary& summary, const std::string& title);
// Where a headless run's outputs sit on one timeline, in seconds from frame 0.
struct OutputTimeline {
  double fps = 30.0;
  double wav_start = 0.0;     // the WAV's first sample
  double speech_start = 0.0;  // the first sample of speech in it (the lead-in)
};

// JSON with the summary per stage and the raw per-frame samples, and the
// timeline when given. A write error (a full disk: a short write, a failed
// flush or close) removes the file and throws std::runtime_error "cannot
// write timing JSON PATH: reason".
void WriteTimingJson(const std::filesystem::path& path, const TimingSummary& summary,
                     const std::vector<FrameSample>& samples, const std::string& rig_name,
                     std::size_t vertex_count, std::size_t shape_count,
                     const std::optional<OutputTimeline>& timeline = std::nullopt);

}  // namespace facerig::player
