#include "cli/options.h"
#include "bench/lipsync.h"
#include "bench/common.h"
#include "bench/json.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "measure/lip_probe.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/speech/phoneme_visemes.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using facerig::Percentile;

constexpr double kSampleStep = 0.001;  // 1 kHz aperture sampling for closure and lag
constexpr double kFrameStep = 1.0 / 60.0;
constexpr double kEnvelopeHop = 0.005;  // lag resolution

std::vector<std::string> ReadLines(const fs::path& path) {
  std::vector<std::string> lines;
  if (!fs::exists(path)) return lines;  // as before: a missing corpus file is an empty one
  std::istringstream in(facerig::ReadInputText(path, std::uint64_t{16} << 20));
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// RMS of the audio in windows of 2 hops centred on each hop.
std::vector<double> RmsEnvelope(const facerig::SpeechLine& line, std::size_t hops) {
  std::vector<double> envelope(hops, 0.0);
  const double rate = line.sample_rate;
  for (std::size_t h = 0; h < hops; ++h) {
    const double centre = static_cast<double>(h) * kEnvelopeHop;
    const auto begin = static_cast<std::int64_t>((centre - kEnvelopeHop) * rate);
    const auto end = static_cast<std::int64_t>((centre + kEnvelopeHop) * rate);
    double sum = 0.0;
    std::int64_t n = 0;
    for (std::int64_t i = std::max<std::int64_t>(begin, 0);
         i < std::min<std::int64_t>(end, static_cast<std::int64_t>(line.audio.size())); ++i, ++n) {
      const double s = line.audio[static_cast<std::size_t>(i)] / 32768.0;
      sum += s * s;
    }
    envelope[h] = n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
  }
  return envelope;
}

void Standardize(std::vector<double>& values) {
  if (values.empty()) return;
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  double var = 0.0;
  for (double v : values) var += (v - mean) * (v - mean);
  const double sd = std::sqrt(var / static_cast<double>(values.size()));
  for (double& v : values) v = sd > 0.0 ? (v - mean) / sd : 0.0;
}

struct BlinkStats {
  double per_min = 0.0;
  double median_duration_ms = 0.0;
  double interval_mean = 0.0;
  double interval_median = 0.0;
  double double_share = 0.0;
};

BlinkStats SimulateHour(bool talking, std::uint64_t seed) {
  const facerig::BlinkParams params;
  std::vector<facerig::BlinkActivity> activity;
  if (talking) {
    // Phrases of 2.5 s separated by 0.5 s pauses, as in conversation.
    for (double t = 0.0; t < 3600.0; t += 3.0) {
      activity.push_back({t, t + 2.5, true, false});
      activity.push_back({t + 2.5, t + 3.0, true, true});
    }
  } else {
    activity.push_back({0.0, 3600.0, false, false});
  }
  std::vector<facerig::BlinkEvent> events(4000);
  std::size_t count = 0;
  if (facerig::SimulateBlinks(params, seed, 0.0, 3600.0, activity, events, &count) != facerig::BlinkError::kNone) {
    return {};
  }
  events.resize(count);
  BlinkStats stats;
  stats.per_min = static_cast<double>(count) / 60.0;
  std::vector<double> durations, intervals;
  std::size_t doubles = 0;
  for (std::size_t i = 0; i < count; ++i) {
    durations.push_back(events[i].duration * 1000.0);
    if (i > 0) intervals.push_back(events[i].start - events[i - 1].start);
    doubles += events[i].second_of_double ? 1 : 0;
  }
  stats.median_duration_ms = Percentile(durations, 0.5);
  stats.interval_median = Percentile(intervals, 0.5);
  stats.interval_mean = intervals.empty() ? 0.0
                                          : std::accumulate(intervals.begin(), intervals.end(), 0.0) /
                                                static_cast<double>(intervals.size());
  stats.double_share = count > 0 ? static_cast<double>(doubles) / static_cast<double>(count) : 0.0;
  return stats;
}

struct LipsyncOptions {
  std::string rig_path = FACERIG_DEFAULT_ICT_DIR;
  std::string corpus_path = std::string(FACERIG_DEFAULT_CORPUS_DIR) + "/en.txt";
  std::string voice = "en-us";
  std::string json_path;
  std::size_t max_lines = 0;
};

// The rig, the corpus lines and the ICT lip midline vertices; false after
// printing why not.
bool LoadInputs(const LipsyncOptions& options, facerig::Rig& rig, std::vector<std::string>& lines,
                std::optional<std::array<std::uint32_t, 2>>& lip_vertices) {
  const std::string& rig_path = options.rig_path;
  try {
    rig = facerig::LoadRigOrTemplateFolder(rig_path);
    lines = ReadLines(options.corpus_path);
    lip_vertices = facerig::IctInnerLipVertices(rig_path);
  } catch (const facerig::IoError& error) {
    ReportBenchFailure(error);
    return false;
  }
  if (lines.empty()) {
    std::fprintf(stderr, "facerig-bench: %s has no sentences\n", options.corpus_path.c_str());
    return false;
  }
  if (options.max_lines > 0 && lines.size() > options.max_lines) lines.resize(options.max_lines);
  if (!lip_vertices) {
    std::fprintf(stderr, "facerig-bench: lipsync needs the ICT-FaceKit landmark list "
                         "(vertex_indices.json) to find the lip midline vertices\n");
    return false;
  }
  return true;
}

// What the corpus run accumulates over its lines.
struct CorpusMeasures {
  std::size_t bilabials = 0, closed_bilabials = 0;
  std::vector<double> steps_relative, update_us;
  std::vector<double> pooled_correlation = std::vector<double>(81, 0.0);  // lags -200..+200 ms in 5 ms hops
  std::size_t pooled_samples = 0;
};

// The lip aperture at 1 kHz over `duration`, timing every 17th update.
std::vector<double> SampleAperture(facerig::Character& character, const facerig::LipProbe& probe, double duration,
                                   std::vector<double>& update_us) {
  const auto samples = static_cast<std::size_t>(duration / kSampleStep) + 1;
  std::vector<double> aperture(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    const double t = static_cast<double>(i) * kSampleStep;
    const auto update_start = Clock::now();
    (void)character.Update(facerig::Seconds(t));
    if (i % 17 == 0) {
      update_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - update_start).count());
    }
    aperture[i] = probe.Aperture(character.weights());
  }
  return aperture;
}

// Bilabial closure within each p/b/m interval (p's closure precedes its release event).
void CountBilabialClosures(const facerig::SpeechLine& line, const std::vector<double>& aperture, double max_aperture,
                           const facerig::CharacterParams& params, CorpusMeasures& measures) {
  const std::size_t samples = aperture.size();
  for (const facerig::Phoneme& phoneme : line.phonemes) {
    const auto map = facerig::LookupPhonemeVisemes(phoneme.language.view(), phoneme.symbol.view());
    if (!map || map->count == 0 || map->visemes[0] != facerig::Viseme::kPP) continue;
    ++measures.bilabials;
    const double begin = phoneme.start.count() -
                         (map->has(facerig::PhonemeVisemes::kUnvoicedStop) ? params.timing.stop_closure : 0.0);
    const double end = phoneme.start.count() + std::max(phoneme.duration.count(), params.timing.min_duration);
    double lowest = max_aperture;
    for (double t = std::max(0.0, begin); t <= end; t += kSampleStep) {
      lowest = std::min(lowest, aperture[std::min(samples - 1, static_cast<std::size_t>(t / kSampleStep + 0.5))]);
    }
    measures.closed_bilabials += lowest <= 0.05 * max_aperture ? 1 : 0;
  }
}

// Smoothness: aperture steps per 60 fps frame, relative to the line's largest aperture.
void AddFrameSteps(const std::vector<double>& aperture, double duration, double max_aperture,
                   std::vector<double>& steps_relative) {
  const std::size_t samples = aperture.size();
  double previous = aperture[0];
  for (double t = kFrameStep; t < duration; t += kFrameStep) {
    const double current = aperture[std::min(samples - 1, static_cast<std::size_t>(t / kSampleStep + 0.5))];
    steps_relative.push_back(std::abs(current - previous) / max_aperture);
    previous = current;
  }
}

// Cross-correlation of aperture and audio RMS on a 5 ms grid (pooled over lines).
void AddLagCorrelation(const facerig::SpeechLine& line, const std::vector<double>& aperture,
                       CorpusMeasures& measures) {
  const std::size_t samples = aperture.size();
  const auto hops = static_cast<std::size_t>(line.audio_duration().count() / kEnvelopeHop);
  std::vector<double> envelope = RmsEnvelope(line, hops);
  std::vector<double> mouth(hops);
  for (std::size_t h = 0; h < hops; ++h) mouth[h] = aperture[std::min(samples - 1, h * 5)];
  Standardize(envelope);
  Standardize(mouth);
  for (int lag = -40; lag <= 40; ++lag) {
    double sum = 0.0;
    for (std::size_t h = 0; h < hops; ++h) {
      const auto m = static_cast<std::int64_t>(h) + lag;  // mouth `lag` hops after the audio
      if (m >= 0 && m < static_cast<std::int64_t>(hops)) sum += envelope[h] * mouth[static_cast<std::size_t>(m)];
    }
    measures.pooled_correlation[static_cast<std::size_t>(lag + 40)] += sum;
  }
  measures.pooled_samples += hops;
}

// The measured part over the corpus: each line spoken by a fresh character.
// Returns the exit code: 0, or 1 after printing why a line failed.
int MeasureCorpus(const std::vector<std::string>& lines, const std::string& voice,
                  facerig::EspeakPhonemeSource& source, const facerig::CharacterRig& character_rig,
                  const facerig::CharacterParams& params, const facerig::LipProbe& probe, CorpusMeasures& measures) {
  for (const std::string& text : lines) {
    facerig::SpeechLine line;
    try {
      line = source.Synthesize(text, voice);
    } catch (const facerig::SpeechError& error) {
      return ReportBenchFailure(error);
    }
    facerig::Character character(character_rig, params);
    if (character.Speak(line.phonemes, facerig::Seconds(0.0)) != facerig::CharacterError::kNone) {
      std::fprintf(stderr, "facerig-bench: cannot schedule '%s'\n", text.c_str());
      return 1;
    }
    // Aperture at 1 kHz over the line (+0.3 s of release).
    const double duration = line.audio_duration().count() + 0.3;
    const std::vector<double> aperture = SampleAperture(character, probe, duration, measures.update_us);
    const double max_aperture = *std::max_element(aperture.begin(), aperture.end());
    if (max_aperture <= 0.0) continue;
    CountBilabialClosures(line, aperture, max_aperture, params, measures);
    AddFrameSteps(aperture, duration, max_aperture, measures.steps_relative);
    AddLagCorrelation(line, aperture, measures);
  }
  return 0;
}

// Text -> audio + viseme keys for a 20-word sentence (the corpus lines are
// shorter), milliseconds per run.
std::vector<double> TimeTextToVisemes(facerig::EspeakPhonemeSource& source, const std::string& voice,
                                      const facerig::CharacterRig& character_rig,
                                      const facerig::CharacterParams& params) {
  constexpr const char* kTwentyWords =
      "Please bring me the blue box from the small room before the bus leaves for the market at five.";
  std::vector<double> tts_ms;
  for (int run = 0; run < 15; ++run) {
    const auto start = Clock::now();
    const facerig::SpeechLine line = source.Synthesize(kTwentyWords, voice);
    facerig::Character character(character_rig, params);
    (void)character.Speak(line.phonemes, facerig::Seconds(0.0));
    tts_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return tts_ms;
}

// Share of phonemes mapped to visemes per voice, over the corpus folder's
// one-paragraph files (en.txt where a language has none).
nlohmann::json MappedPhonemeShares(facerig::EspeakPhonemeSource& source, const std::string& corpus_path) {
  nlohmann::json languages = nlohmann::json::object();
  const fs::path corpus_dir = fs::path(corpus_path).parent_path();
  for (const char* language : {"en-us", "en", "pt-br", "pt", "es", "fr", "de", "it", "fi", "nl", "pl", "ru", "hi", "cmn"}) {
    fs::path file = corpus_dir / (std::string(language) + ".txt");
    if (!fs::exists(file)) file = corpus_dir / "en.txt";
    std::size_t total = 0, mapped = 0;
    for (const std::string& text : ReadLines(file)) {
      try {
        const facerig::SpeechLine line = source.Synthesize(text, language);
        total += line.phonemes.size();
        std::size_t unmapped = 0;
        for (const auto& u : facerig::FindUnmappedSymbols(line.phonemes)) unmapped += u.count;
        mapped += line.phonemes.size() - unmapped;
      } catch (const facerig::SpeechError& error) {
        std::fprintf(stderr, "facerig-bench: %s: %s\n", language, error.what());
      }
      if (file.filename() == "en.txt" && total > 2000) break;
    }
    languages[language] = total > 0 ? static_cast<double>(mapped) / static_cast<double>(total) : 0.0;
  }
  return languages;
}

double WorstShare(const nlohmann::json& languages) {
  double worst = 1.0;
  for (const auto& [name, share] : languages.items()) worst = std::min(worst, share.get<double>());
  return worst;
}

// The numbers the table and the JSON report.
struct LipsyncSummary {
  std::size_t bilabials = 0, closed_bilabials = 0;
  double closure_rate = 0.0;
  double av_lag_ms = 0.0;
  double peak_correlation = 0.0;
  double p99_step = 0.0;
  double update_median = 0.0;
  double tts_median = 0.0;
  std::size_t tts_runs = 0;
  BlinkStats rest, talking;
  nlohmann::json languages;
};

LipsyncSummary Summarize(const CorpusMeasures& measures, const std::vector<double>& tts_ms) {
  LipsyncSummary summary;
  const std::vector<double>& pooled_correlation = measures.pooled_correlation;
  const auto best = std::max_element(pooled_correlation.begin(), pooled_correlation.end());
  summary.av_lag_ms = (static_cast<double>(best - pooled_correlation.begin()) - 40.0) * kEnvelopeHop * 1000.0;
  summary.peak_correlation =
      measures.pooled_samples > 0 ? *best / static_cast<double>(measures.pooled_samples) : 0.0;
  summary.bilabials = measures.bilabials;
  summary.closed_bilabials = measures.closed_bilabials;
  summary.closure_rate = measures.bilabials > 0 ? static_cast<double>(measures.closed_bilabials) /
                                                      static_cast<double>(measures.bilabials)
                                                : 0.0;
  summary.p99_step = Percentile(measures.steps_relative, 0.99);
  summary.update_median = Percentile(measures.update_us, 0.5);
  summary.tts_median = Percentile(tts_ms, 0.5);
  summary.tts_runs = tts_ms.size();
  return summary;
}

void PrintTable(const LipsyncSummary& s) {
  std::printf("\n| measure | value | target |\n|---|---|---|\n");
  std::printf("| bilabial closure rate (p/b/m reaching <= 5%% of max aperture) | %.1f%% (%zu / %zu) | 100%% |\n",
              100.0 * s.closure_rate, s.closed_bilabials, s.bilabials);
  std::printf("| audio-visual lag (aperture vs audio RMS, + = mouth late) | %+.0f ms (r = %.2f) | within +-20 ms |\n",
              s.av_lag_ms, s.peak_correlation);
  std::printf("| aperture p99 step per 60 fps frame | %.1f%% of max aperture | reported |\n", 100.0 * s.p99_step);
  std::printf("| blinks at rest / talking (simulated hour) | %.1f / %.1f per min | ~17 / ~26 |\n", s.rest.per_min,
              s.talking.per_min);
  std::printf("| blink interval mean / median at rest | %.2f / %.2f s | right-skewed, mean ~3.5 s |\n",
              s.rest.interval_mean, s.rest.interval_median);
  std::printf("| blink duration median | %.0f ms | 150-400 ms |\n", s.rest.median_duration_ms);
  std::printf("| double blinks | %.1f%% | occasional |\n", 100.0 * s.rest.double_share);
  std::printf("| Character::Update (no blend), median | %.2f us | <= 5 us |\n", s.update_median);
  std::printf("| text -> audio + viseme keys, 20 words, median | %.1f ms (%zu runs) | <= 30 ms |\n",
              s.tts_median, s.tts_runs);
  std::printf("| phonemes mapped, worst voice | %.1f%% | 100%% |\n", 100.0 * WorstShare(s.languages));
}

nlohmann::json ReportJson(const LipsyncOptions& options, std::size_t sentences, const LipsyncSummary& s) {
  return {{"corpus", options.corpus_path},
          {"voice", options.voice},
          {"rig", options.rig_path},
          {"sentences", sentences},
          {"bilabials", s.bilabials},
          {"bilabial_closure_rate", s.closure_rate},
          {"av_lag_ms", s.av_lag_ms},
          {"av_peak_correlation", s.peak_correlation},
          {"aperture_p99_step", s.p99_step},
          {"blinks_per_min_talking", s.talking.per_min},
          {"blinks_per_min_rest", s.rest.per_min},
          {"blink_duration_ms_median", s.rest.median_duration_ms},
          {"blink_interval_mean_s", s.rest.interval_mean},
          {"blink_interval_median_s", s.rest.interval_median},
          {"double_blink_share", s.rest.double_share},
          {"update_us", s.update_median},
          {"tts_ready_ms", s.tts_median},
          {"languages", s.languages}};
}

}  // namespace

int RunLipsyncBenchmark(int argc, char** argv) {
  LipsyncOptions options;
  CLI::App app("closure, audio-visual lag, smoothness, blinks, cost", "facerig-bench lipsync");
  app.add_option("--rig", options.rig_path, "the rig (default: the ICT-FaceKit folder)");
  app.add_option("--corpus", options.corpus_path, "corpus text, a line per utterance");
  app.add_option("--voice", options.voice, "espeak-ng voice (default en-us)");
  app.add_option("--json", options.json_path, "write the results as JSON");
  app.add_option("--lines", options.max_lines, "only the first N lines (default all)");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  facerig::Rig rig;
  std::vector<std::string> lines;
  std::optional<std::array<std::uint32_t, 2>> lip_vertices;
  if (!LoadInputs(options, rig, lines, lip_vertices)) return 1;
  const facerig::LipProbe probe(rig, (*lip_vertices)[0], (*lip_vertices)[1]);
  const facerig::CharacterRig character_rig = facerig::CharacterRig::Build(rig);
  for (const std::string& warning : character_rig.warnings()) std::printf("rig warning: %s\n", warning.c_str());
  facerig::CharacterParams params;
  facerig::EspeakPhonemeSource source;

  std::printf("lipsync: %zu sentences (%s, voice %s) on %s\n", lines.size(), options.corpus_path.c_str(),
              options.voice.c_str(), options.rig_path.c_str());
  CorpusMeasures measures;
  if (const int exit_code = MeasureCorpus(lines, options.voice, source, character_rig, params, probe, measures)) {
    return exit_code;
  }
  LipsyncSummary summary = Summarize(measures, TimeTextToVisemes(source, options.voice, character_rig, params));
  summary.rest = SimulateHour(false, 1);
  summary.talking = SimulateHour(true, 1);
  summary.languages = MappedPhonemeShares(source, options.corpus_path);
  PrintTable(summary);
  if (!options.json_path.empty()) return WriteBenchJson(options.json_path, ReportJson(options, lines.size(), summary));
  return 0;
}
