#include "bench/align_confidence.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>

#include "bench/recordings.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "measure/alignment_scoring.h"

namespace {

using facerig::test::Quantile;

struct Clip {
  std::string name, text;
  facerig::AudioClip audio;
};

std::vector<Clip> RealClips(const std::vector<std::string>& folders) {
  std::vector<Clip> clips;
  for (const std::string& folder : folders) {
    if (!std::filesystem::exists(TranscriptionFile(folder))) continue;
    for (const BenchRecording& r : ReadTranscription(folder)) clips.push_back({r.id, r.text, facerig::ReadAudioFile(r.wav)});
  }
  return clips;
}

std::vector<Clip> SyntheticClips(const std::vector<std::string>& sentences, facerig::PhonemeSource& recorder) {
  std::vector<Clip> clips;
  for (const std::string& sentence : sentences) {
    const facerig::SpeechLine line = recorder.Synthesize(sentence, "en-us");
    facerig::AudioClip audio;
    audio.sample_rate = line.sample_rate;
    audio.channels_in_file = 1;
    audio.samples = facerig::PcmToFloat(line.audio);
    clips.push_back({sentence.substr(0, 24), sentence, audio});
  }
  return clips;
}

// White noise of `seconds` at RMS 0.1 (-20 dBFS), 16 kHz.
facerig::AudioClip WhiteNoise(double seconds, std::mt19937& random) {
  facerig::AudioClip clip;
  clip.sample_rate = 16000;
  clip.channels_in_file = 1;
  std::normal_distribution<float> noise(0.0f, 0.1f);
  clip.samples.resize(static_cast<std::size_t>(seconds * clip.sample_rate));
  for (float& s : clip.samples) s = noise(random);
  return clip;
}

struct Distribution {
  std::vector<double> values, tempi;
  std::vector<std::string> wrong_side;  // pairs the threshold classifies wrongly
};

// Adds the pair's confidence and tempo to `d`; returns whether it passes `threshold` (TranscriptFits).
bool Measure(facerig::PhonemeSource& aligner, const facerig::AudioClip& clip, const std::string& text,
             double threshold, Distribution& d) {
  const facerig::PhonemeAlignment a = facerig::AlignRecording(aligner, clip, text, "en-us").alignment;
  d.values.push_back(a.confidence);
  d.tempi.push_back(a.tempo);
  return facerig::TranscriptFits(a, threshold);
}

nlohmann::json DistributionJson(const Distribution& d) {
  return {{"pairs", d.values.size()},
          {"min", Quantile(d.values, 0.0)},
          {"p10", Quantile(d.values, 0.1)},
          {"median", Quantile(d.values, 0.5)},
          {"p90", Quantile(d.values, 0.9)},
          {"max", Quantile(d.values, 1.0)},
          {"wrong_side", d.wrong_side},
          {"tempo_min", Quantile(d.tempi, 0.0)},
          {"tempo_p10", Quantile(d.tempi, 0.1)},
          {"tempo_median", Quantile(d.tempi, 0.5)},
          {"tempo_p90", Quantile(d.tempi, 0.9)},
          {"tempo_max", Quantile(d.tempi, 1.0)},
          {"values", d.values},
          {"tempi", d.tempi}};
}

void PrintRow(const char* what, const Distribution& d) {
  std::printf("| %s | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %zu | %.2f-%.2f |\n", what, d.values.size(),
              Quantile(d.values, 0.0), Quantile(d.values, 0.1), Quantile(d.values, 0.5), Quantile(d.values, 0.9),
              Quantile(d.values, 1.0), d.wrong_side.size(), Quantile(d.tempi, 0.0), Quantile(d.tempi, 1.0));
}

// Each clip with its own transcript (matched), with every other clip's
// (mismatched); each transcript with white noise as long as its clip.
nlohmann::json MeasureSet(const std::vector<Clip>& clips, facerig::PhonemeSource& aligner, double threshold,
                          const char* label) {
  Distribution matched, mismatched, noise;
  std::mt19937 random(3);
  for (std::size_t i = 0; i < clips.size(); ++i) {
    for (std::size_t t = 0; t < clips.size(); ++t) {
      Distribution& d = i == t ? matched : mismatched;
      const bool fits = Measure(aligner, clips[i].audio, clips[t].text, threshold, d);
      if ((i == t) != fits) d.wrong_side.push_back(clips[i].name + " / " + clips[t].name);
    }
    const facerig::AudioClip white = WhiteNoise(std::max(1.0, clips[i].audio.duration_seconds()), random);
    if (Measure(aligner, white, clips[i].text, threshold, noise)) noise.wrong_side.push_back("noise / " + clips[i].name);
  }
  std::printf("\n%s: match confidence (threshold %.2f, and the tempo within a factor of 2: TranscriptFits)\n\n| pairs | n | min | p10 | median | p90 | max | "
              "on the wrong side | tempo |\n|---|---|---|---|---|---|---|---|---|\n", label, threshold);
  PrintRow("own transcript", matched);
  PrintRow("another line's", mismatched);
  PrintRow("white noise", noise);
  return {{"matched", DistributionJson(matched)},
          {"mismatched", DistributionJson(mismatched)},
          {"noise", DistributionJson(noise)}};
}

}  // namespace

nlohmann::json MeasureConfidence(const ConfidenceBenchOptions& options, facerig::PhonemeSource& recorder,
                                 facerig::PhonemeSource& aligner) {
  nlohmann::json json = {{"threshold", options.min_confidence}};
  const std::vector<Clip> real = RealClips(options.recordings_dirs);
  if (!real.empty()) json["real"] = MeasureSet(real, aligner, options.min_confidence, "real recordings");
  if (!options.sentences.empty()) {
    json["synthetic"] = MeasureSet(SyntheticClips(options.sentences, recorder), aligner, options.min_confidence,
                                   "espeak-ng recordings (another voice and rate)");
  }
  return json;
}
