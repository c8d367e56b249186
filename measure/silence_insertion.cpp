#include "measure/silence_insertion.h"

#include <cmath>
#include <vector>

#include "facerig/runtime/audio/features.h"

namespace facerig::test {

std::size_t MiddleWord(const SpeechLine& line) {
  const double middle = 0.5 * line.audio_duration().count();
  std::size_t best = 0;
  for (std::size_t i = 1; i < line.phonemes.size(); ++i) {
    if (!line.phonemes[i].word_start) continue;
    if (best == 0 || std::abs(line.phonemes[i].start.count() - middle) <
                         std::abs(line.phonemes[best].start.count() - middle)) {
      best = i;
    }
  }
  return best;
}

SilencedRecording WithSilence(const SpeechLine& spoken, const SilenceLayout& layout, std::mt19937& random) {
  SilencedRecording r;
  r.truth = spoken;
  r.truth.audio.clear();
  const std::vector<float> speech = PcmToFloat(spoken.audio);
  const auto samples = [&](double seconds) { return static_cast<std::size_t>(seconds * spoken.sample_rate); };
  std::size_t cut = speech.size();
  if (layout.inside > 0.0) {
    r.inner = MiddleWord(spoken);
    if (r.inner > 0) cut = samples(spoken.phonemes[r.inner].start.count());
  }
  std::vector<float>& out = r.clip.samples;
  out.assign(samples(layout.before), 0.0f);
  out.insert(out.end(), speech.begin(), speech.begin() + static_cast<std::ptrdiff_t>(cut));
  if (cut < speech.size()) out.resize(out.size() + samples(layout.inside), 0.0f);
  out.insert(out.end(), speech.begin() + static_cast<std::ptrdiff_t>(cut), speech.end());
  out.resize(out.size() + samples(layout.after), 0.0f);
  std::normal_distribution<float> noise(0.0f, kRoomNoiseRms);
  for (float& s : out) s += noise(random);
  r.clip.sample_rate = spoken.sample_rate;
  r.clip.channels_in_file = 1;
  const double before = static_cast<double>(samples(layout.before)) / spoken.sample_rate;
  const double inserted = static_cast<double>(samples(layout.inside)) / spoken.sample_rate;
  for (std::size_t i = 0; i < r.truth.phonemes.size(); ++i) {
    r.truth.phonemes[i].start += Seconds(before + (r.inner > 0 && i >= r.inner ? inserted : 0.0));
  }
  return r;
}

}  // namespace facerig::test
