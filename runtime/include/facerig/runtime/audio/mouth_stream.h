// The rough mode (audio_mouth.h) for audio that arrives in chunks, e.g. a
// cloud TTS stream without timestamps: phonemes come out with a bounded delay
// (latency(), under 0.3 s with the default params).
//
// Same features, classes and symbols as RoughMouthFromAudio; it differs in
// what it cannot know in advance: the noise floor and loud level are tracked
// (AudioMouthParams::floor_rise_db_per_second, loud_fall_db_per_second)
// instead of taken from the whole buffer, short segments are merged within a
// look-ahead window, and a long segment comes out in pieces of at most
// 100 ms (consecutive phonemes with the same symbol). Not for a real-time
// thread: Push may allocate (its buffers grow to the largest chunk, and `out`).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "facerig/runtime/audio/mouth.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

class RoughMouthStream {
 public:
  // A bad sample rate or analysis params (see AnalyzeMouthFrames) make an
  // invalid stream: valid() is false and it emits nothing.
  explicit RoughMouthStream(int sample_rate, const AudioMouthParams& params = {});
  ~RoughMouthStream();
  RoughMouthStream(RoughMouthStream&&) noexcept;
  RoughMouthStream& operator=(RoughMouthStream&&) noexcept;

  bool valid() const;
  // After a Push with audio up to time T, the phonemes out so far cover at
  // least [0, T - latency()]. Seconds; 0 for an invalid stream.
  double latency() const;

  // Appends the phonemes that became final to `out` (in time order,
  // contiguous from 0). Samples as in AnalyzeMouthFrames.
  void Push(std::span<const float> samples, std::vector<Phoneme>& out);
  void Push(std::span<const std::int16_t> samples, std::vector<Phoneme>& out);
  // End of the line: the remaining phonemes, up to the end of the audio; the
  // stream is then ready for a new line.
  void Finish(std::vector<Phoneme>& out);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace facerig
