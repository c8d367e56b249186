#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/offline/geometry/stats.h"

#include <chrono>
#include <vector>

namespace facerig {

RecordingAlignment AlignRecording(PhonemeSource& source, const AudioClip& recording, std::string_view transcript,
                                  std::string_view voice, const PhonemeAlignmentParams& params) {
  const auto start = std::chrono::steady_clock::now();
  RecordingAlignment result;
  result.reference = source.Synthesize(transcript, voice);
  if (result.reference.phonemes.empty() || result.reference.audio.empty()) {
    throw AlignmentError("the transcript gives no speech to align");
  }
  const std::vector<float> samples =
      ResampleAudio(recording.samples, recording.sample_rate, result.reference.sample_rate);
  result.alignment = AlignPhonemesToRecording(result.reference, samples, params);
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace facerig
