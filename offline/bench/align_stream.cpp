#include "bench/align_stream.h"

#include <algorithm>
#include <chrono>
#include <span>
#include <vector>

facerig::RecordingAlignment StreamAlign(facerig::PhonemeSource& aligner, const facerig::AudioClip& clip,
                                        const std::string& sentence, const std::string& voice, double chunk_ms,
                                        const facerig::StreamingAlignmentParams& params) {
  const auto start = std::chrono::steady_clock::now();
  facerig::RecordingAlignment result;
  result.reference = aligner.Synthesize(sentence, voice);
  const std::vector<float> samples = facerig::ResampleAudio(clip.samples, clip.sample_rate, result.reference.sample_rate);
  facerig::StreamingAligner streaming(result.reference, params);
  facerig::SpeechLine& line = result.alignment.line;
  line = result.reference;
  line.audio.clear();
  const auto take = [&](std::span<const facerig::StreamedBoundary> boundaries) {
    for (const facerig::StreamedBoundary& b : boundaries) line.phonemes[b.phoneme].start = b.start;
  };
  const auto chunk =
      std::max<std::size_t>(1, static_cast<std::size_t>(chunk_ms * 1e-3 * result.reference.sample_rate));
  for (std::size_t at = 0; at < samples.size(); at += chunk) {
    take(streaming.Push(std::span<const float>(samples).subspan(at, std::min(chunk, samples.size() - at))));
  }
  take(streaming.Finish());
  const double end = clip.duration_seconds();
  for (std::size_t i = 0; i < line.phonemes.size(); ++i) {
    const double next = i + 1 < line.phonemes.size() ? line.phonemes[i + 1].start.count() : end;
    line.phonemes[i].duration = facerig::Seconds(std::max(0.0, next - line.phonemes[i].start.count()));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}
