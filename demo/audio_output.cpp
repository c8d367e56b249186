#include "audio_output.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace facerig::player {

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

AudioOutput::~AudioOutput() {
  if (device_ != 0) SDL_CloseAudioDevice(device_);
}

bool AudioOutput::Open(int sample_rate, AudioClock* clock, std::string* error) {
  if (SDL_InitSubSystem(SDL_INIT_AUDIO) != 0) {
    *error = std::string("SDL audio: ") + SDL_GetError();
    return false;
  }
  SDL_AudioSpec wanted{};
  wanted.freq = sample_rate;
  wanted.format = AUDIO_S16SYS;
  wanted.channels = 1;
  wanted.samples = 512;  // ~23 ms at 22050 Hz: one callback period of clock uncertainty
  wanted.callback = &AudioOutput::Callback;
  wanted.userdata = this;
  SDL_AudioSpec obtained{};
  // No allowed changes: SDL converts, so the callback counts samples at our rate.
  device_ = SDL_OpenAudioDevice(nullptr, 0, &wanted, &obtained, 0);
  if (device_ == 0) {
    *error = std::string("SDL_OpenAudioDevice: ") + SDL_GetError();
    return false;
  }
  clock_ = clock;
  sample_rate_ = sample_rate;
  latency_seconds_ = static_cast<double>(obtained.samples) / sample_rate;
  AudioClockParams params;
  params.sample_rate = sample_rate;
  params.output_latency_seconds = latency_seconds_;
  params.default_period_seconds = latency_seconds_;
  clock_->Configure(params);
  // Time 0 is device sample 0 (nothing has been pulled yet: the device is paused).
  base_sample_ = 0;
  base_time_ = 0.0;
  clock_->Start(WallSeconds(), 0);
  SDL_PauseAudioDevice(device_, 0);
  return true;
}

void AudioOutput::Callback(void* user, Uint8* stream, int length) {
  auto* self = static_cast<AudioOutput*>(user);
  const auto wanted = static_cast<std::size_t>(length) / sizeof(std::int16_t);
  const std::size_t available = std::min(wanted, self->buffer_.size() - self->read_);
  // An empty buffer has a null data(), which memcpy may not be given even for 0 bytes.
  if (available > 0) {
    std::memcpy(stream, self->buffer_.data() + self->read_, available * sizeof(std::int16_t));
  }
  std::memset(stream + available * sizeof(std::int16_t), 0, (wanted - available) * sizeof(std::int16_t));
  self->read_ += available;
  self->consumed_ += static_cast<std::int64_t>(wanted);
  // The samples just handed over have been consumed as of now.
  self->clock_->OnDeviceProgress(self->consumed_, WallSeconds());
}

double AudioOutput::Play(std::span<const std::int16_t> samples) {
  SDL_LockAudioDevice(device_);
  buffer_.assign(samples.begin(), samples.end());
  read_ = 0;
  const std::int64_t first_sample = consumed_;
  SDL_UnlockAudioDevice(device_);
  return base_time_ + static_cast<double>(first_sample - base_sample_) / sample_rate_;
}

void AudioOutput::SetPaused(bool paused) {
  const double wall = WallSeconds();
  if (paused) {
    SDL_PauseAudioDevice(device_, 1);
    clock_->Stop(wall);
    return;
  }
  // The clock resumes from where it stopped, at the device's current sample.
  base_time_ = clock_->Now(wall);
  SDL_LockAudioDevice(device_);
  base_sample_ = consumed_;
  SDL_UnlockAudioDevice(device_);
  clock_->Start(wall, base_sample_);
  SDL_PauseAudioDevice(device_, 0);
}

}  // namespace facerig::player
