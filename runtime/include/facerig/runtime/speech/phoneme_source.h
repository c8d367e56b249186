// Where timed phonemes come from. The runtime core only knows this interface;
// the espeak-ng implementation (GPL-3) lives in its own target, facerig::espeak.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

// A failure to produce speech: unknown voice, missing engine data, bad text.
class SpeechError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Receives a line while it is being synthesized (streaming mode). Calls come
// from the source's worker thread, in time order; a receiver that feeds a
// real-time thread must hand data over without blocking it (e.g. a ring buffer).
class SpeechStreamReceiver {
 public:
  virtual ~SpeechStreamReceiver() = default;
  virtual void OnStart(int sample_rate) = 0;
  virtual void OnAudio(std::span<const std::int16_t> samples) = 0;
  virtual void OnPhoneme(const Phoneme& phoneme) = 0;
  virtual void OnEnd() = 0;
};

class PhonemeSource {
 public:
  virtual ~PhonemeSource() = default;
  // Schedule-ahead mode: the whole line (audio + phonemes) before playback.
  // Throws SpeechError.
  virtual SpeechLine Synthesize(std::string_view text, std::string_view voice) = 0;
  // Streaming mode: audio chunks and phonemes as they are produced; returns
  // when the line is done. Throws SpeechError (before any callback for bad
  // arguments).
  virtual void SynthesizeStreaming(std::string_view text, std::string_view voice,
                                   SpeechStreamReceiver& receiver) = 0;
  // Voice names this source accepts, e.g. "en-us".
  virtual std::vector<std::string> Voices() const = 0;
};

}  // namespace facerig
