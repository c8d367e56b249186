#include "cli_options.h"
#include "bench_lipsync.h"
#include "bench_json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/lip_probe.h"
#include "facerig/offline/stats.h"
#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/error.h"
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
  std::ifstream in(path);
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

}  // namespace

int RunLipsyncBenchmark(int argc, char** argv) {
  std::string rig_path = FACERIG_DEFAULT_ICT_DIR;
  std::string corpus_path = std::string(FACERIG_DEFAULT_CORPUS_DIR) + "/en.txt";
  std::string voice = "en-us";
  std::string json_path;
  std::size_t max_lines = 0;
  CLI::App app("closure, audio-visual lag, smoothness, blinks, cost", "facerig-bench lipsync");
  app.add_option("--rig", rig_path, "the rig (default: the ICT-FaceKit folder)");
  app.add_option("--corpus", corpus_path, "corpus text, a line per utterance");
  app.add_option("--voice", voice, "espeak-ng voice (default en-us)");
  app.add_option("--json", json_path, "write the results as JSON");
  app.add_option("--lines", max_lines, "only the first N lines (default all)");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  facerig::Rig rig;
  std::vector<std::string> lines;
  std::optional<std::array<std::uint32_t, 2>> lip_vertices;
  try {
    rig = facerig::LoadRigOrTemplateFolder(rig_path);
    lines = ReadLines(corpus_path);
    lip_vertices = facerig::IctInnerLipVertices(rig_path);
  } catch (const facerig::IoError& error) {
    std::fprintf(stderr, "facerig-bench: %s\n", error.what());
    return 1;
  }
  if (lines.empty()) {
    std::fprintf(stderr, "facerig-bench: %s has no sentences\n", corpus_path.c_str());
    return 1;
  }
  if (max_lines > 0 && lines.size() > max_lines) lines.resize(max_lines);
  if (!lip_vertices) {
    std::fprintf(stderr, "facerig-bench: lipsync needs the ICT-FaceKit landmark list "
                         "(vertex_indices.json) to find the lip midline vertices\n");
    return 1;
  }
  const facerig::LipProbe probe(rig, (*lip_vertices)[0], (*lip_vertices)[1]);
  const facerig::CharacterRig character_rig = facerig::CharacterRig::Build(rig);
  for (const std::string& warning : character_rig.warnings()) std::printf("rig warning: %s\n", warning.c_str());
  facerig::CharacterParams params;
  facerig::EspeakPhonemeSource source;

  std::size_t bilabials = 0, closed_bilabials = 0;
  std::vector<double> steps_relative, tts_ms, update_us;
  std::vector<double> pooled_correlation(81, 0.0);  // lags -200..+200 ms in 5 ms hops
  std::size_t pooled_samples = 0;
  std::printf("lipsync: %zu sentences (%s, voice %s) on %s\n", lines.size(), corpus_path.c_str(),
              voice.c_str(), rig_path.c_str());
  for (const std::string& text : lines) {
    facerig::SpeechLine line;
    try {
      line = source.Synthesize(text, voice);
    } catch (const facerig::SpeechError& error) {
      std::fprintf(stderr, "facerig-bench: %s\n", error.what());
      return 1;
    }
    facerig::Character character(character_rig, params);
    if (character.Speak(line.phonemes, facerig::Seconds(0.0)) != facerig::CharacterError::kNone) {
      std::fprintf(stderr, "facerig-bench: cannot schedule '%s'\n", text.c_str());
      return 1;
    }

    // Aperture at 1 kHz over the line (+0.3 s of release).
    const double duration = line.audio_duration().count() + 0.3;
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
    const double max_aperture = *std::max_element(aperture.begin(), aperture.end());
    if (max_aperture <= 0.0) continue;

    // Bilabial closure within each p/b/m interval (p's closure precedes its release event).
    for (const facerig::Phoneme& phoneme : line.phonemes) {
      const auto map = facerig::LookupPhonemeVisemes(phoneme.language.view(), phoneme.symbol.view());
      if (!map || map->count == 0 || map->visemes[0] != facerig::Viseme::kPP) continue;
      ++bilabials;
      const double begin = phoneme.start.count() -
                           (map->has(facerig::PhonemeVisemes::kUnvoicedStop) ? params.timing.stop_closure : 0.0);
      const double end = phoneme.start.count() + std::max(phoneme.duration.count(), params.timing.min_duration);
      double lowest = max_aperture;
      for (double t = std::max(0.0, begin); t <= end; t += kSampleStep) {
        lowest = std::min(lowest, aperture[std::min(samples - 1, static_cast<std::size_t>(t / kSampleStep + 0.5))]);
      }
      closed_bilabials += lowest <= 0.05 * max_aperture ? 1 : 0;
    }

    // Smoothness at 60 fps.
    double previous = aperture[0];
    for (double t = kFrameStep; t < duration; t += kFrameStep) {
      const double current = aperture[std::min(samples - 1, static_cast<std::size_t>(t / kSampleStep + 0.5))];
      steps_relative.push_back(std::abs(current - previous) / max_aperture);
      previous = current;
    }

    // Cross-correlation of aperture and audio RMS on a 5 ms grid (pooled over lines).
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
      pooled_correlation[static_cast<std::size_t>(lag + 40)] += sum;
    }
    pooled_samples += hops;
  }
  const auto best = std::max_element(pooled_correlation.begin(), pooled_correlation.end());
  const double av_lag_ms = (static_cast<double>(best - pooled_correlation.begin()) - 40.0) * kEnvelopeHop * 1000.0;
  const double peak_correlation = pooled_samples > 0 ? *best / static_cast<double>(pooled_samples) : 0.0;

  // Text -> audio + viseme keys for a 20-word sentence (the corpus lines are shorter).
  constexpr const char* kTwentyWords =
      "Please bring me the blue box from the small room before the bus leaves for the market at five.";
  for (int run = 0; run < 15; ++run) {
    const auto start = Clock::now();
    const facerig::SpeechLine line = source.Synthesize(kTwentyWords, voice);
    facerig::Character character(character_rig, params);
    (void)character.Speak(line.phonemes, facerig::Seconds(0.0));
    tts_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }

  const BlinkStats rest = SimulateHour(false, 1);
  const BlinkStats talking = SimulateHour(true, 1);

  // Phonemes mapped per voice, over the corpus folder's one-paragraph files.
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
        mapped += line.phonemes.size() - [&] {
          std::size_t unmapped = 0;
          for (const auto& u : facerig::FindUnmappedSymbols(line.phonemes)) unmapped += u.count;
          return unmapped;
        }();
      } catch (const facerig::SpeechError& error) {
        std::fprintf(stderr, "facerig-bench: %s: %s\n", language, error.what());
      }
      if (file.filename() == "en.txt" && total > 2000) break;
    }
    languages[language] = total > 0 ? static_cast<double>(mapped) / static_cast<double>(total) : 0.0;
  }

  const double closure_rate = bilabials > 0 ? static_cast<double>(closed_bilabials) / static_cast<double>(bilabials) : 0.0;
  const double p99_step = Percentile(steps_relative, 0.99);
  const double update_median = Percentile(update_us, 0.5);
  const double tts_median = Percentile(tts_ms, 0.5);
  std::printf("\n| measure | value | target |\n|---|---|---|\n");
  std::printf("| bilabial closure rate (p/b/m reaching <= 5%% of max aperture) | %.1f%% (%zu / %zu) | 100%% |\n",
              100.0 * closure_rate, closed_bilabials, bilabials);
  std::printf("| audio-visual lag (aperture vs audio RMS, + = mouth late) | %+.0f ms (r = %.2f) | within +-20 ms |\n",
              av_lag_ms, peak_correlation);
  std::printf("| aperture p99 step per 60 fps frame | %.1f%% of max aperture | reported |\n", 100.0 * p99_step);
  std::printf("| blinks at rest / talking (simulated hour) | %.1f / %.1f per min | ~17 / ~26 |\n", rest.per_min,
              talking.per_min);
  std::printf("| blink interval mean / median at rest | %.2f / %.2f s | right-skewed, mean ~3.5 s |\n",
              rest.interval_mean, rest.interval_median);
  std::printf("| blink duration median | %.0f ms | 150-400 ms |\n", rest.median_duration_ms);
  std::printf("| double blinks | %.1f%% | occasional |\n", 100.0 * rest.double_share);
  std::printf("| Character::Update (no blend), median | %.2f us | <= 5 us |\n", update_median);
  std::printf("| text -> audio + viseme keys, 20 words, median | %.1f ms (%zu runs) | <= 30 ms |\n",
              tts_median, tts_ms.size());
  std::printf("| phonemes mapped, worst voice | %.1f%% | 100%% |\n", [&] {
    double worst = 1.0;
    for (const auto& [name, share] : languages.items()) worst = std::min(worst, share.get<double>());
    return 100.0 * worst;
  }());

  if (!json_path.empty()) {
    nlohmann::json report = {{"corpus", corpus_path},
                             {"voice", voice},
                             {"rig", rig_path},
                             {"sentences", lines.size()},
                             {"bilabials", bilabials},
                             {"bilabial_closure_rate", closure_rate},
                             {"av_lag_ms", av_lag_ms},
                             {"av_peak_correlation", peak_correlation},
                             {"aperture_p99_step", p99_step},
                             {"blinks_per_min_talking", talking.per_min},
                             {"blinks_per_min_rest", rest.per_min},
                             {"blink_duration_ms_median", rest.median_duration_ms},
                             {"blink_interval_mean_s", rest.interval_mean},
                             {"blink_interval_median_s", rest.interval_median},
                             {"double_blink_share", rest.double_share},
                             {"update_us", update_median},
                             {"tts_ready_ms", tts_median},
                             {"languages", languages}};
    return WriteBenchJson(json_path, report);
  }
  return 0;
}
