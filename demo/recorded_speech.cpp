#include "recorded_speech.h"

#include <stdexcept>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/audio/mouth.h"
#include "facerig/runtime/io/phoneme_track_file.h"

namespace facerig::player {
namespace {

// The track's phonemes, and the audio it names when --audio does not.
SpeechLine TrackLine(const PlayerOptions& options, std::filesystem::path* audio) {
  PhonemeTrack track = ReadPhonemeTrack(options.track);
  if (audio->empty()) {
    if (track.audio_path.empty()) {
      throw std::runtime_error(options.track.string() + ": the track names no audio file; give --audio FILE");
    }
    try {
      *audio = ResolveInsideFolder(options.track, track.audio_path, "/audio");
    } catch (const IoError& e) {
      throw IoError(e.kind(), e.path(), e.message() + "; give the recording with --audio FILE");
    }
  }
  return std::move(track.line);
}

// The rough mode's line for a recording without transcript or track.
SpeechLine RoughLine(const AudioClip& clip, const std::filesystem::path& path) {
  std::optional<SpeechLine> line = RoughMouthFromAudio(clip.samples, clip.sample_rate);
  if (!line) {
    throw IoError(IoErrorKind::kUnsupportedFormat, path.string(),
                  "sample rate " + std::to_string(clip.sample_rate) + " Hz is outside what the rough mode reads");
  }
  return std::move(*line);
}

}  // namespace

bool WantsRecordedSpeech(const PlayerOptions& options) { return !options.audio.empty() || !options.track.empty(); }

bool WantsRoughMode(const PlayerOptions& options) {
  return !options.audio.empty() && options.text.empty() && options.track.empty();
}

SpeechLine LoadRecordedSpeech(const PlayerOptions& options, int sample_rate) {
  std::filesystem::path audio_path = options.audio;
  SpeechLine line;
  if (!options.track.empty()) line = TrackLine(options, &audio_path);
  const AudioClip clip = ReadAudioFile(audio_path);
  if (WantsRoughMode(options)) {
    line = RoughLine(clip, audio_path);
  } else if (options.track.empty()) {
    EspeakPhonemeSource source;
    line = AlignRecording(source, clip, options.text, options.voice).alignment.line;
  }
  const int rate = sample_rate > 0 ? sample_rate : clip.sample_rate;
  line.sample_rate = rate;
  line.audio = FloatToPcm(ResampleAudio(clip.samples, clip.sample_rate, rate));
  return line;
}

}  // namespace facerig::player
