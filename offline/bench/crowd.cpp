#include "cli/options.h"
#include "bench/crowd.h"
#include "bench/common.h"
#include "bench/json.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/error.h"
#include "facerig/offline/io/template_folder.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kFrameBudgetUs = 1e6 / 60.0;

constexpr const char* kLines[] = {
    "Bring me the map before the boat leaves the bay.",
    "Five brave men moved the big piano up the stairs.",
    "Please pass the bread and the butter, my friend.",
    "We will meet by the fountain when the bells ring.",
    "My father bought a purple van at the fair.",
    "The baby popped the bubble and laughed.",
    "Maybe the museum opens before nine on Mondays.",
    "Very few people visit the vast empty beach in winter.",
};

// One character: its controller plus the output buffers sized once.
struct CrowdMember {
  std::unique_ptr<facerig::Character> character;
  std::vector<glm::vec3> positions, normals;
  double line_length = 0.0;
  double offset = 0.0;
};

// Characters speaking the lines in turn, each with its own seed, start time
// and emotion, and output buffers sized once.
std::vector<CrowdMember> MakeCrowd(std::size_t count, const facerig::CharacterRig& character_rig,
                                   const std::vector<facerig::SpeechLine>& lines, std::size_t vertex_count) {
  std::vector<CrowdMember> crowd(count);
  for (std::size_t i = 0; i < count; ++i) {
    facerig::CharacterParams params;
    params.seed = i;
    CrowdMember& member = crowd[i];
    member.character = std::make_unique<facerig::Character>(character_rig, params);
    const facerig::SpeechLine& line = lines[i % lines.size()];
    member.offset = 0.37 * static_cast<double>(i % 11);  // characters start at different times
    member.line_length = line.audio_duration().count();
    (void)member.character->Speak(line.phonemes, facerig::Seconds(member.offset));
    member.character->SetEmotion(static_cast<facerig::Emotion>(i % facerig::kEmotionCount), 0.5f);
    member.positions.resize(vertex_count);
    member.normals.resize(vertex_count);
  }
  return crowd;
}

// Microseconds per frame: the whole frame, and the summed update and blend parts.
struct FrameTimes {
  std::vector<double> frame_us, update_us_total, blend_us_total;
};

// The measured part. One core: the frame loop runs on this thread only.
FrameTimes RunFrames(std::vector<CrowdMember>& crowd, const facerig::Rig& rig, bool with_normals, int frames) {
  FrameTimes times;
  for (int frame = 0; frame < frames; ++frame) {
    const double time = 0.5 + static_cast<double>(frame) / 60.0;
    double update_us = 0.0, blend_us = 0.0;
    const auto frame_start = Clock::now();
    for (CrowdMember& member : crowd) {
      const auto t0 = Clock::now();
      (void)member.character->Update(facerig::Seconds(time));
      const auto t1 = Clock::now();
      const facerig::BlendJob job{&rig, member.character->weights(),
                                  with_normals ? facerig::NormalMode::kRecompute : facerig::NormalMode::kNone,
                                  member.positions, member.normals};
      (void)job.Run();
      const auto t2 = Clock::now();
      update_us += std::chrono::duration<double, std::micro>(t1 - t0).count();
      blend_us += std::chrono::duration<double, std::micro>(t2 - t1).count();
    }
    times.frame_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - frame_start).count());
    times.update_us_total.push_back(update_us);
    times.blend_us_total.push_back(blend_us);
  }
  return times;
}

// The p99 by the floor index into the sorted values (unlike facerig::Percentile).
double FloorP99(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(0.99 * static_cast<double>(v.size() - 1))];
}

struct CrowdSummary {
  double frame_median = 0.0;
  double frame_p99 = 0.0;
  double update_per_character_us = 0.0;
  double blend_per_character_us = 0.0;
  double per_character_us = 0.0;
  std::size_t max_characters = 0;  // within one 60 fps frame
};

CrowdSummary Summarize(const FrameTimes& times, std::size_t count) {
  CrowdSummary s;
  s.frame_median = UpperMedian(times.frame_us);
  s.frame_p99 = FloorP99(times.frame_us);
  s.update_per_character_us = UpperMedian(times.update_us_total) / static_cast<double>(count);
  s.blend_per_character_us = UpperMedian(times.blend_us_total) / static_cast<double>(count);
  s.per_character_us = s.frame_median / static_cast<double>(count);
  s.max_characters = static_cast<std::size_t>(kFrameBudgetUs / s.per_character_us);
  return s;
}

void PrintTable(const CrowdSummary& s) {
  std::printf("| frame (all characters) median / p99 | %.0f / %.0f us (budget %.0f us at 60 fps) |\n",
              s.frame_median, s.frame_p99, kFrameBudgetUs);
  std::printf("| per character: update / blend / total | %.2f / %.2f / %.2f us |\n", s.update_per_character_us,
              s.blend_per_character_us, s.per_character_us);
  std::printf("| largest N within one 60 fps frame | %zu |\n", s.max_characters);
}

}  // namespace

int RunCrowdBenchmark(int argc, char** argv) {
  std::size_t count = 100;
  std::string rig_path = FACERIG_DEFAULT_HEAD;
  if (!std::filesystem::exists(rig_path)) rig_path = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  bool with_normals = false;
  int frames = 240;
  CLI::App app("N characters' update + blend per 60 fps frame on one core", "facerig-bench crowd");
  app.add_option("count", count, "characters (default 100)")->check(facerig::cli::InRange(std::size_t{1}, std::size_t{1000000}));
  app.add_option("--rig", rig_path, "the rig (default: the built-in head)");
  app.add_flag("--normals", with_normals, "blend normals too");
  app.add_option("--frames", frames, "frames (default 240)")->check(facerig::cli::InRange(10, 1000000));
  app.add_option("--json", json_path, "write the results as JSON");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  facerig::Rig rig;
  try {
    rig = facerig::LoadRigOrTemplateFolder(rig_path);
  } catch (const facerig::IoError& error) {
    return ReportBenchFailure(error);
  }
  const facerig::CharacterRig character_rig = facerig::CharacterRig::Build(rig);
  facerig::EspeakPhonemeSource source;
  std::vector<facerig::SpeechLine> lines;
  for (const char* text : kLines) lines.push_back(source.Synthesize(text, "en-us"));

  std::vector<CrowdMember> crowd = MakeCrowd(count, character_rig, lines, rig.vertex_count());
  const CrowdSummary summary = Summarize(RunFrames(crowd, rig, with_normals, frames), count);
  std::printf("crowd: %zu characters on %s (%zu vertices, %zu shapes), %s, %d frames, one core\n", count,
              rig_path.c_str(), rig.vertex_count(), rig.shape_count(),
              with_normals ? "positions + recomputed normals" : "positions", frames);
  PrintTable(summary);
  if (!json_path.empty()) {
    const nlohmann::json report = {{"rig", rig_path},
                                   {"characters", count},
                                   {"normals", with_normals},
                                   {"frame_us_median", summary.frame_median},
                                   {"frame_us_p99", summary.frame_p99},
                                   {"update_us_per_character", summary.update_per_character_us},
                                   {"blend_us_per_character", summary.blend_per_character_us},
                                   {"per_character_us", summary.per_character_us},
                                   {"max_characters_60fps", summary.max_characters}};
    return WriteBenchJson(json_path, report);
  }
  return 0;
}
