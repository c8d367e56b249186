#include "cli/options.h"
#include "bench/crowd.h"
#include "bench/common.h"
#include "bench/crowd_accuracy.h"
#include "bench/crowd_roofline.h"
#include "bench/json.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/crowd_blend_job.h"
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

// One way to blend a crowd: today's whole-mesh path (no state) or only
// what moves (a BlendState per character); positions, or with normals.
struct Config {
  const char* name;
  bool sparse;
  facerig::NormalMode normals;
};
constexpr Config kConfigs[] = {
    {"whole mesh (before), positions", false, facerig::NormalMode::kNone},
    {"only what moves, positions", true, facerig::NormalMode::kNone},
    {"whole mesh (before), + recomputed normals", false, facerig::NormalMode::kRecompute},
    {"only what moves (positions), + recomputed normals", true, facerig::NormalMode::kRecompute},
    {"only what moves, + blended recomputed normals", true, facerig::NormalMode::kBlendRecomputedDeltas},
};
// Indices into kConfigs for the comparisons.
constexpr std::size_t kWholePositions = 0, kSparsePositions = 1, kWholeNormals = 2, kSparseRecomputed = 3,
                      kSparseBlended = 4;

// One character: its controller plus the output buffers sized once.
struct Speaker {
  std::unique_ptr<facerig::Character> character;
  std::vector<glm::vec3> positions, normals;
  std::unique_ptr<facerig::BlendState> state;  // null: the whole-mesh path
};

// Characters speaking the lines in turn, each with its own seed, start time
// and emotion, and output buffers sized once. Every crowd made with the same
// count is the same crowd.
std::vector<Speaker> MakeCrowd(std::size_t count, const facerig::CharacterRig& character_rig,
                                   const std::vector<facerig::SpeechLine>& lines, const facerig::BlendPlan* plan) {
  std::vector<Speaker> crowd(count);
  for (std::size_t i = 0; i < count; ++i) {
    facerig::CharacterParams params;
    params.seed = i;
    Speaker& member = crowd[i];
    member.character = std::make_unique<facerig::Character>(character_rig, params);
    const double offset = 0.37 * static_cast<double>(i % 11);  // characters start at different times
    (void)member.character->Speak(lines[i % lines.size()].phonemes, facerig::Seconds(offset));
    member.character->SetEmotion(static_cast<facerig::Emotion>(i % facerig::kEmotionCount), 0.5f);
    member.positions.resize(character_rig.rig().vertex_count());
    member.normals.resize(character_rig.rig().vertex_count());
    if (plan) member.state = std::make_unique<facerig::BlendState>(*plan);
  }
  return crowd;
}

// Microseconds per frame: the whole frame, and the summed update and blend parts.
struct FrameTimes {
  std::vector<double> frame_us, update_us_total, blend_us_total;
  std::vector<facerig::CrowdMember> members;  // the crowd job's, reused every frame
};

// One frame of one crowd on this thread (one core): each character's update,
// then its blend (the whole-mesh path), or one CrowdBlendJob for all of them
// (only what moves).
void RunFrame(std::vector<Speaker>& crowd, const facerig::Rig& rig, facerig::NormalMode normals, double time,
              FrameTimes& times) {
  double update_us = 0.0, blend_us = 0.0;
  const auto frame_start = Clock::now();
  if (crowd.front().state) {
    std::vector<facerig::CrowdMember>& members = times.members;
    members.resize(crowd.size());  // once: the first frame
    for (std::size_t i = 0; i < crowd.size(); ++i) {
      Speaker& member = crowd[i];
      (void)member.character->Update(facerig::Seconds(time));
      members[i] = {member.character->weights(), member.positions, member.normals, member.state.get()};
    }
    const auto t1 = Clock::now();
    (void)facerig::CrowdBlendJob{&rig, normals, members}.Run();
    update_us = std::chrono::duration<double, std::micro>(t1 - frame_start).count();
    blend_us = std::chrono::duration<double, std::micro>(Clock::now() - t1).count();
  } else {
    for (Speaker& member : crowd) {
      const auto t0 = Clock::now();
      (void)member.character->Update(facerig::Seconds(time));
      const auto t1 = Clock::now();
      const facerig::BlendJob job{&rig, member.character->weights(), normals, member.positions, member.normals};
      (void)job.Run();
      const auto t2 = Clock::now();
      update_us += std::chrono::duration<double, std::micro>(t1 - t0).count();
      blend_us += std::chrono::duration<double, std::micro>(t2 - t1).count();
    }
  }
  times.frame_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - frame_start).count());
  times.update_us_total.push_back(update_us);
  times.blend_us_total.push_back(blend_us);
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

// Every chosen configuration's crowd, frame by frame in turn, so that all see
// the same load; the roofline kernel in turn too. A first pass counts the
// sparse normals crowd's work after each of its frames.
struct CrowdRun {
  std::vector<FrameTimes> times;  // per configuration (empty: not run)
  std::vector<double> roofline_us;  // per frame, all characters
  CrowdWork work;                   // median character-frame
  double worst_smooth_degrees = 0.0, worst_degrees = 0.0, smooth_share = 0.0;  // NormalAccuracy's
  std::size_t accuracy_samples = 0;
};

// The census's first characters (one per line, each with another emotion)
// every fourth frame: their blended normals against recomputed ones.
constexpr std::size_t kAccuracyCharacters = std::size(kLines);
constexpr int kAccuracyEvery = 4;

// A first pass of the lit crowd that writes only what moves: the median
// character-frame's work, which the roofline is sized to, and the normals
// of its first characters against recomputed ones.
void Census(const facerig::Rig& rig, const facerig::BlendPlan& plan, const facerig::CharacterRig& character_rig,
            const std::vector<facerig::SpeechLine>& lines, std::size_t count, int frames, CrowdRun& run) {
  std::vector<Speaker> census = MakeCrowd(count, character_rig, lines, &plan);
  NormalAccuracy accuracy(rig);
  std::vector<CrowdWork> work;
  FrameTimes ignored;
  for (int frame = 0; frame < frames; ++frame) {
    RunFrame(census, rig, kConfigs[kSparseBlended].normals, 0.5 + frame / 60.0, ignored);
    for (std::size_t i = 0; i < census.size(); ++i) {
      const std::span<const float> w = census[i].character->weights();
      work.push_back(CountWork(plan, {w.begin(), w.end()}, *census[i].state));
      if (i < kAccuracyCharacters && frame % kAccuracyEvery == 0) accuracy.Add(w, census[i].normals);
    }
  }
  run.work = MedianWork(work);
  run.worst_smooth_degrees = accuracy.worst_smooth_degrees();
  run.worst_degrees = accuracy.worst_degrees();
  run.smooth_share = accuracy.smooth_share();
  run.accuracy_samples = accuracy.samples();
}

CrowdRun RunCrowds(const facerig::Rig& rig, const facerig::CharacterRig& character_rig,
                   const std::vector<facerig::SpeechLine>& lines, std::size_t count, int frames, bool normals_only) {
  const facerig::BlendPlan plan = facerig::BlendPlan::Build(rig);
  std::vector<std::vector<Speaker>> crowds;
  for (const Config& config : kConfigs) {
    const bool chosen = !normals_only || config.normals != facerig::NormalMode::kNone;
    crowds.push_back(chosen ? MakeCrowd(count, character_rig, lines, config.sparse ? &plan : nullptr) : std::vector<Speaker>{});
  }
  CrowdRun run;
  run.times.resize(std::size(kConfigs));
  Census(rig, plan, character_rig, lines, count, frames, run);
  CrowdRoofline roofline(run.work, count);
  for (int frame = 0; frame < frames; ++frame) {
    const double time = 0.5 + static_cast<double>(frame) / 60.0;
    for (std::size_t c = 0; c < std::size(kConfigs); ++c) {
      if (!crowds[c].empty()) RunFrame(crowds[c], rig, kConfigs[c].normals, time, run.times[c]);
    }
    const auto start = Clock::now();
    for (std::size_t i = 0; i < count; ++i) roofline.Run(i);
    run.roofline_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  if (roofline.Checksum() == 1.5f) std::printf(" ");  // keeps the roofline's work
  return run;
}

// `summaries` per configuration; null: not run.
void PrintTable(const std::vector<std::optional<CrowdSummary>>& summaries) {
  std::printf("| blend | frame median / p99 (us) | per character: update / blend / total (us) | characters per 60 fps frame |\n");
  std::printf("|---|---|---|---|\n");
  for (std::size_t c = 0; c < summaries.size(); ++c) {
    if (!summaries[c]) continue;
    const CrowdSummary& s = *summaries[c];
    std::printf("| %s | %.0f / %.0f | %.2f / %.2f / %.2f | %zu |\n", kConfigs[c].name, s.frame_median, s.frame_p99,
                s.update_per_character_us, s.blend_per_character_us, s.per_character_us, s.max_characters);
  }
  const auto speedup = [&](std::size_t before, std::size_t after) {
    return summaries[before]->per_character_us / summaries[after]->per_character_us;
  };
  std::printf("same run, per character against the whole mesh:");
  if (summaries[kWholePositions]) std::printf(" positions %.2fx faster;", speedup(kWholePositions, kSparsePositions));
  std::printf(" with normals, recomputed %.2fx, blended %.2fx faster\n", speedup(kWholeNormals, kSparseRecomputed),
              speedup(kWholeNormals, kSparseBlended));
}

void PrintRoofline(const CrowdWork& work, double roofline_us, const CrowdSummary& sparse, double update_us) {
  const double bytes = work.Bytes();
  std::printf("\nthe median character-frame (only what moves, + blended recomputed normals): %.0f active shapes;\n"
              "%.0f position deltas onto %.0f vertices, %.0f normal-sum terms onto %.0f normals:\n"
              "%.0f kB must move (each delta read once, each touched vertex's rest read and output written once)\n",
              work.active_shapes, work.entries, work.moved_vertices, work.normal_entries, work.shaded_vertices,
              bytes / 1e3);
  std::printf("roofline (streaming those bytes, each character's outputs its own): %.1f us per character (%.1f GB/s),\n"
              "%.0f characters per 60 fps frame with the update; the blend takes %.1f us: %.2fx the roofline\n",
              roofline_us, bytes / (roofline_us * 1e3), kFrameBudgetUs / (roofline_us + update_us),
              sparse.blend_per_character_us, sparse.blend_per_character_us / roofline_us);
}

nlohmann::json SummaryJson(const Config& config, const CrowdSummary& s) {
  return {{"blend", config.name},
          {"only_what_moves", config.sparse},
          {"normals", config.normals == facerig::NormalMode::kNone ? "none"
                      : config.normals == facerig::NormalMode::kRecompute ? "recomputed" : "blended recomputed deltas"},
          {"frame_us_median", s.frame_median},
          {"frame_us_p99", s.frame_p99},
          {"update_us_per_character", s.update_per_character_us},
          {"blend_us_per_character", s.blend_per_character_us},
          {"per_character_us", s.per_character_us},
          {"max_characters_60fps", s.max_characters}};
}

}  // namespace

int RunCrowdBenchmark(int argc, char** argv) {
  std::size_t count = 100;
  std::string rig_path = FACERIG_DEFAULT_HEAD;
  if (!std::filesystem::exists(rig_path)) rig_path = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  int frames = 240;
  bool normals_only = false;
  CLI::App app("N characters' update + blend per 60 fps frame on one core: the whole-mesh blend and only what moves",
               "facerig-bench crowd");
  app.add_option("count", count, "characters (default 100)")->check(facerig::cli::InRange(std::size_t{1}, std::size_t{1000000}));
  app.add_option("--rig", rig_path, "the rig (default: the built-in head)");
  app.add_option("--frames", frames, "frames (default 240)")->check(facerig::cli::InRange(10, 1000000));
  app.add_flag("--normals", normals_only, "only the blends with normals (a lit crowd): leave out positions only");
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

  const CrowdRun run = RunCrowds(rig, character_rig, lines, count, frames, normals_only);
  std::vector<std::optional<CrowdSummary>> summaries;
  for (const FrameTimes& times : run.times) {
    summaries.push_back(times.frame_us.empty() ? std::nullopt : std::optional(Summarize(times, count)));
  }
  const CrowdSummary& blended = *summaries[kSparseBlended];
  const double roofline_us = UpperMedian(run.roofline_us) / static_cast<double>(count);
  std::printf("crowd: %zu characters on %s (%zu vertices, %zu shapes), %d frames, one core, each blend in turn\n",
              count, rig_path.c_str(), rig.vertex_count(), rig.shape_count(), frames);
  PrintTable(summaries);
  PrintRoofline(run.work, roofline_us, blended, blended.update_per_character_us);
  std::printf("blended recomputed normals against recomputed ones (%zu vertex-frames): max %.2f degree where smooth "
              "(%.1f %% of them), %.2f everywhere; target: 1 degree where smooth\n",
              run.accuracy_samples, run.worst_smooth_degrees, 100.0 * run.smooth_share, run.worst_degrees);
  if (json_path.empty()) return 0;
  nlohmann::json report = {{"rig", rig_path},
                           {"characters", count},
                           {"frames", frames},
                           {"work", {{"active_shapes", run.work.active_shapes},
                                     {"position_deltas", run.work.entries},
                                     {"moved_vertices", run.work.moved_vertices},
                                     {"normal_deltas", run.work.normal_entries},
                                     {"shaded_vertices", run.work.shaded_vertices},
                                     {"bytes", run.work.Bytes()}}},
                           {"roofline_characters_60fps",
                            kFrameBudgetUs / (roofline_us + blended.update_per_character_us)},
                           {"roofline_us_per_character", roofline_us},
                           {"blend_over_roofline", blended.blend_per_character_us / roofline_us},
                           {"normals_worst_smooth_degrees", run.worst_smooth_degrees},
                           {"normals_worst_degrees", run.worst_degrees},
                           {"normals_smooth_share", run.smooth_share}};
  for (std::size_t c = 0; c < summaries.size(); ++c) {
    if (summaries[c]) report["blends"].push_back(SummaryJson(kConfigs[c], *summaries[c]));
  }
  return WriteBenchJson(json_path, report);
}
