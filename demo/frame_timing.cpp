#include "frame_timing.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "media_writer.h"

namespace facerig::player {

const char* ToString(Stage stage) {
  switch (stage) {
    case Stage::kUpdate: return "update";
    case Stage::kBlend: return "blend";
    case Stage::kUpload: return "upload";
    case Stage::kDraw: return "draw";
  }
  return "?";
}

double FrameSample::total_ms() const {
  double total = 0.0;
  for (double value : ms) total += value;
  return total;
}

FrameTimer::FrameTimer(std::size_t reserve_frames) { samples_.reserve(reserve_frames); }

void FrameTimer::BeginFrame() {
  current_ = FrameSample{};
  last_ = Clock::now();
}

void FrameTimer::Mark(Stage stage) {
  const Clock::time_point now = Clock::now();
  current_.ms[static_cast<std::size_t>(stage)] +=
      std::chrono::duration<double, std::milli>(now - last_).count();
  last_ = now;
}

void FrameTimer::EndFrame() { samples_.push_back(current_); }

namespace {

StageSummary Summarize(std::vector<double>& values) {
  StageSummary summary;
  if (values.empty()) return summary;
  std::sort(values.begin(), values.end());
  // Nearest-rank percentiles.
  const auto at = [&](double p) {
    const auto rank = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1) + 0.5);
    return values[std::min(rank, values.size() - 1)];
  };
  summary.p50 = at(0.50);
  summary.p95 = at(0.95);
  summary.p99 = at(0.99);
  summary.worst = values.back();
  double sum = 0.0;
  for (double value : values) sum += value;
  summary.mean = sum / static_cast<double>(values.size());
  return summary;
}

}  // namespace

TimingSummary FrameTimer::Summarize(std::size_t window) const {
  TimingSummary summary;
  const std::size_t count = window == 0 ? samples_.size() : std::min(window, samples_.size());
  const std::size_t first = samples_.size() - count;
  summary.frames = count;
  std::vector<double> values(count);
  for (std::size_t s = 0; s < kStageCount; ++s) {
    for (std::size_t i = 0; i < count; ++i) values[i] = samples_[first + i].ms[s];
    summary.stages[s] = player::Summarize(values);
  }
  double worst = -1.0;
  for (std::size_t i = 0; i < count; ++i) {
    values[i] = samples_[first + i].total_ms();
    if (values[i] > worst) {
      worst = values[i];
      summary.worst_frame = first + i;
    }
  }
  summary.total = player::Summarize(values);
  return summary;
}

std::string FormatSummary(const TimingSummary& summary, const std::string& title) {
  std::string text;
  char line[256];
  std::snprintf(line, sizeof(line), "%s: %zu frames, CPU ms per frame (p50 / p95 / p99 / worst)\n",
                title.c_str(), summary.frames);
  text += line;
  const auto row = [&](const char* name, const StageSummary& s) {
    std::snprintf(line, sizeof(line), "  %-8s %8.3f %8.3f %8.3f %8.3f\n", name, s.p50, s.p95, s.p99,
                  s.worst);
    text += line;
  };
  for (std::size_t s = 0; s < kStageCount; ++s) row(ToString(static_cast<Stage>(s)), summary.stages[s]);
  row("total", summary.total);
  std::snprintf(line, sizeof(line), "  worst frame: %zu\n", summary.worst_frame);
  text += line;
  return text;
}

void WriteTimingJson(const std::filesystem::path& path, const TimingSummary& summary,
                     const std::vector<FrameSample>& samples, const std::string& rig_name,
                     std::size_t vertex_count, std::size_t shape_count,
                     const std::optional<OutputTimeline>& timeline) {
  using nlohmann::json;
  const auto stage_json = [](const StageSummary& s) {
    return json{{"p50_ms", s.p50}, {"p95_ms", s.p95}, {"p99_ms", s.p99}, {"worst_ms", s.worst},
                {"mean_ms", s.mean}};
  };
  json out;
  out["rig"] = rig_name;
  out["vertices"] = vertex_count;
  out["shapes"] = shape_count;
  out["frames"] = summary.frames;
  out["worst_frame"] = summary.worst_frame;
  out["total"] = stage_json(summary.total);
  json stages = json::object();
  for (std::size_t s = 0; s < kStageCount; ++s) {
    stages[ToString(static_cast<Stage>(s))] = stage_json(summary.stages[s]);
  }
  out["stages"] = stages;
  json per_frame = json::array();
  for (const FrameSample& sample : samples) per_frame.push_back(sample.ms);
  out["per_frame_ms"] = per_frame;
  out["per_frame_columns"] = {"update", "blend", "upload", "draw"};
  if (timeline) {
    out["timeline"] = {{"frame0_seconds", 0.0},
                       {"fps", timeline->fps},
                       {"wav_start_seconds", timeline->wav_start},
                       {"speech_start_seconds", timeline->speech_start}};
  }
  const std::string text = out.dump(2) + '\n';
  WriteWholeFile(path, text, "timing JSON");
}

}  // namespace facerig::player
