// Speech audio through SDL2, reporting the device's progress to an AudioClock
// from the audio callback (the animation follows the samples the device pulled).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <SDL.h>

#include "facerig/runtime/audio_clock.h"

namespace facerig::player {

// Seconds on std::chrono::steady_clock: the wall clock both the audio and
// render threads give to AudioClock.
double WallSeconds();

class AudioOutput {
 public:
  AudioOutput() = default;
  ~AudioOutput();
  AudioOutput(const AudioOutput&) = delete;
  AudioOutput& operator=(const AudioOutput&) = delete;

  // Opens the default output device for mono 16-bit audio at `sample_rate`
  // (SDL converts to what the device wants) and starts it, playing silence.
  // Configures and starts `clock` (which must outlive this) on the device.
  // Returns false with the reason when there is no audio device.
  bool Open(int sample_rate, AudioClock* clock, std::string* error);
  bool is_open() const { return device_ != 0; }

  // Replaces what is playing by `samples`. Returns the animation time at
  // which the first sample is heard (seconds on `clock`).
  double Play(std::span<const std::int16_t> samples);
  // Pauses / resumes the device and the clock together.
  void SetPaused(bool paused);
  // Consumed -> audible: one device buffer.
  double latency_seconds() const { return latency_seconds_; }

 private:
  static void Callback(void* user, Uint8* stream, int length);

  SDL_AudioDeviceID device_ = 0;
  AudioClock* clock_ = nullptr;
  int sample_rate_ = 0;
  double latency_seconds_ = 0.0;
  // Guarded by SDL_LockAudioDevice (the callback runs under that lock).
  std::vector<std::int16_t> buffer_;
  std::size_t read_ = 0;
  std::int64_t consumed_ = 0;  // samples the device pulled since Open
  // Device sample <-> clock time: sample base_sample_ is heard at base_time_.
  std::int64_t base_sample_ = 0;
  double base_time_ = 0.0;
};

}  // namespace facerig::player
