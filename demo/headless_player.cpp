#include "headless_player.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include "egl_context.h"
#include "face_animator.h"
#include "face_renderer.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "hud.h"
#include "output_set.h"
#include "recorded_speech.h"

namespace facerig::player {
namespace {

// Where each output is written before OutputSet::Commit() (empty: not written).
struct TemporaryOutputs {
  std::filesystem::path frames, wav, mp4, mp4_wav, timing_json;
};

std::string FramePath(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%05d.png", index);
  return name;
}

bool HasFfmpeg() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

std::string Quote(const std::filesystem::path& path) {
  std::string quoted = "'";
  for (char c : path.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Muxes the frames and `wav` (if any) into `mp4` with ffmpeg.
void WriteMp4(const PlayerOptions& options, const TemporaryOutputs& outputs, const std::filesystem::path& wav) {
  std::string command = "ffmpeg -loglevel error -y -framerate " + std::to_string(options.fps) + " -i " +
                        Quote(outputs.frames / "frame_%05d.png");
  if (!wav.empty()) command += " -i " + Quote(wav) + " -c:a aac";  // both start at frame 0
  command += " -c:v libx264 -pix_fmt yuv420p " + Quote(outputs.mp4);
  if (std::system(command.c_str()) != 0) throw std::runtime_error("ffmpeg failed: " + command);
}

// The --emotion options, and the speech scheduled `options.lead_in` after frame 0.
void StartAnimation(const PlayerOptions& options, FaceAnimator* animator, HeadlessResult* result) {
  for (const auto& [emotion, intensity] : options.emotions) animator->character().SetEmotion(emotion, intensity);
  if (options.recomputed_normals) animator->SetNormalMode(NormalMode::kRecompute);
  result->speech_start = options.lead_in;
  if (!result->speech.phonemes.empty()) {
    const CharacterError speak = animator->character().Speak(result->speech.phonemes, Seconds(result->speech_start));
    if (speak != CharacterError::kNone) throw std::runtime_error(std::string("Speak: ") + ToString(speak));
  }
}

// Where the neutral mouth is in the frames, for the tests (no head rotation).
void MeasureMouth(const FaceAnimator& animator, const FaceRenderer& renderer, const PlayerOptions& options,
                  HeadlessResult* result) {
  const std::optional<glm::vec3> mouth = animator.mouth_center();
  if (!mouth) return;
  result->has_mouth = true;
  result->mouth_pixel = renderer.Project(*mouth, options.width, options.height, glm::mat4(1.0f));
  // Half the mouth's width: about a tenth of the head's size across.
  const glm::vec3 side = glm::vec3(glm::inverse(renderer.rig_to_scene()) *
                                   glm::vec4(renderer.scene_size() * 0.055f, 0.0f, 0.0f, 0.0f));
  result->mouth_radius_pixels = std::abs(
      renderer.Project(*mouth + side, options.width, options.height, glm::mat4(1.0f)).x - result->mouth_pixel.x);
}

// --duration, else the lead-in, the speech and 0.6 s to close the mouth (at least 1 s).
int FrameCount(const PlayerOptions& options, const SpeechLine& speech) {
  const double duration =
      options.duration.value_or(std::max(1.0, options.lead_in + speech.audio_duration().count() + 0.6));
  return std::max(1, static_cast<int>(std::ceil(duration * options.fps - 1e-9)));
}

// Frame i at time i / fps into `frames_dir`, with its timing and lip aperture; the
// result lists the frames under options.frames_dir, where they go at the end.
void RenderFrames(const PlayerOptions& options, const std::filesystem::path& frames_dir, FaceAnimator& animator,
                  FaceRenderer& renderer, OffscreenTarget& target, Hud* hud, HeadlessResult* result) {
  const int frame_count = FrameCount(options, result->speech);
  FrameTimer timer(static_cast<std::size_t>(frame_count));
  Image image;
  for (int frame = 0; frame < frame_count; ++frame) {
    const double time = frame / options.fps;
    timer.BeginFrame();
    animator.Update(time, &timer);
    renderer.Upload(animator.positions(), animator.normals());
    timer.Mark(Stage::kUpload);
    target.Bind();
    renderer.Draw(options.width, options.height, animator.head_rotation());
    if (hud) {
      HudState state = MakeHudState(animator, timer, time);
      hud->Draw(state, options.width, options.height);
    }
    // Offscreen there is no swap to wait on: finish here so the GPU (llvmpipe) work is counted.
    glFinish();
    timer.Mark(Stage::kDraw);
    timer.EndFrame();
    result->lip_aperture.push_back(animator.LipAperture());
    target.Read(&image);
    WritePng(frames_dir / FramePath(frame), image);
    result->frames.push_back(options.frames_dir / FramePath(frame));
    ThrowIfStopped();
  }
  result->samples = timer.samples();
  result->timing = timer.Summarize();
}

bool IsFrameName(const std::filesystem::path& name) {
  return name.string().rfind("frame_", 0) == 0 && name.extension() == ".png";
}

// The WAV the speech goes into beside an MP4 when there is no --wav: FILE.mp4 -> FILE.wav.
std::filesystem::path Mp4Wav(const PlayerOptions& options) {
  std::filesystem::path wav = options.mp4;
  return wav.replace_extension(".wav");
}

// The names of the file outputs that go directly inside the frames folder (a
// WAV beside its frames): they are replaced with it.
std::vector<std::string> OutputsInsideFrames(const PlayerOptions& options, bool mp4_wav) {
  namespace fs = std::filesystem;
  const auto normal = [](const fs::path& path) {
    fs::path absolute = fs::absolute(path).lexically_normal();
    return absolute.has_filename() ? absolute : absolute.parent_path();
  };
  const fs::path frames = normal(options.frames_dir);
  std::vector<std::string> names;
  for (const fs::path& file : {options.wav, options.mp4, mp4_wav ? Mp4Wav(options) : fs::path(), options.timing_json}) {
    if (!file.empty() && normal(file).parent_path() == frames) names.push_back(normal(file).filename().string());
  }
  return names;
}

// The temporary path of each output (OutputSet::Add); empty for those not written.
TemporaryOutputs AddOutputs(const PlayerOptions& options, bool has_speech, OutputSet& set, std::ostream* log) {
  TemporaryOutputs outputs;
  const bool mp4_wav = !options.mp4.empty() && options.wav.empty() && has_speech;
  // The frames folder is replaced as a whole: only one holding nothing but
  // frames (and this run's other outputs that go inside it).
  const ReplaceableFolder frames_folder{[](const std::filesystem::path& name) { return IsFrameName(name); },
                                        "frame_NNNNN.png files", "--frames", OutputsInsideFrames(options, mp4_wav)};
  outputs.frames = set.Add(options.frames_dir, OutputSet::Kind::kFolder, frames_folder);
  if (!options.wav.empty()) outputs.wav = set.Add(options.wav, OutputSet::Kind::kFile);
  if (!options.mp4.empty()) {
    if (mp4_wav) outputs.mp4_wav = set.Add(Mp4Wav(options), OutputSet::Kind::kFile);  // the speech, next to the MP4
    if (HasFfmpeg()) {
      outputs.mp4 = set.Add(options.mp4, OutputSet::Kind::kFile);
    } else if (log != nullptr) {
      *log << "warning: --mp4 needs ffmpeg (Debian: ffmpeg); not written\n";
    }
  }
  if (!options.timing_json.empty()) outputs.timing_json = set.Add(options.timing_json, OutputSet::Kind::kFile);
  return outputs;
}

// --wav, --mp4 (with the speech in a WAV next to it when there is no --wav) and --timing.
void WriteSpeechVideoAndTiming(const PlayerOptions& options, const Rig& rig, const TemporaryOutputs& outputs,
                               HeadlessResult& result) {
  const SpeechLine& speech = result.speech;
  const int rate = speech.sample_rate > 0 ? speech.sample_rate : EspeakPhonemeSource::kSampleRate;
  // The WAV starts with frame 0: the lead-in is silence, so any tool muxes the two in sync.
  std::vector<std::int16_t> audio(static_cast<std::size_t>(std::lround(result.speech_start * rate)), 0);
  audio.insert(audio.end(), speech.audio.begin(), speech.audio.end());
  if (!outputs.wav.empty()) WriteWav(outputs.wav, audio, rate);
  if (!outputs.mp4_wav.empty()) WriteWav(outputs.mp4_wav, audio, rate);
  result.wav_samples = audio.size();
  result.wav_rate = rate;
  ThrowIfStopped();
  if (!outputs.mp4.empty()) WriteMp4(options, outputs, outputs.wav.empty() ? outputs.mp4_wav : outputs.wav);
  ThrowIfStopped();
  if (!outputs.timing_json.empty()) {
    WriteTimingJson(outputs.timing_json, result.timing, result.samples, RigPath(options).filename().string(),
                    rig.vertex_count(), rig.shape_count(),
                    OutputTimeline{.fps = options.fps, .wav_start = 0.0, .speech_start = result.speech_start});
  }
}

// Renders the frames and writes every output under its temporary name.
void RenderAndWrite(const Rig& rig, const PlayerOptions& options, const TemporaryOutputs& outputs,
                    HeadlessResult* result, std::ostream& log) {
  HeadlessGlContext context;
  result->gl_description = context.description();
  IdleLifeParams idle;
  idle.head_motion = idle.saccades = !options.still;
  FaceAnimator animator(rig, idle);
  StartAnimation(options, &animator, result);
  FaceRenderer renderer(rig);
  for (const std::string& problem : renderer.problems()) log << "warning: " << problem << '\n';
  renderer.camera().Orbit(options.yaw_degrees, options.pitch_degrees);
  OffscreenTarget target(options.width, options.height, options.msaa);
  std::optional<Hud> hud;
  if (options.hud) hud.emplace();
  MeasureMouth(animator, renderer, options, result);

  RenderFrames(options, outputs.frames, animator, renderer, target, hud ? &*hud : nullptr, result);
  WriteSpeechVideoAndTiming(options, rig, outputs, *result);
}

}  // namespace

HeadlessResult RunHeadless(const Rig& rig, const PlayerOptions& options, std::ostream& log) {
  HeadlessResult result;
  if (WantsRecordedSpeech(options)) {
    result.speech = LoadRecordedSpeech(options, 0);  // the WAV keeps the recording's rate
  } else if (!options.say.empty()) {
    EspeakPhonemeSource source;
    result.speech = source.Synthesize(options.say, options.voice);
  }
  ThrowIfStopped();
  OutputSet set;  // removes the temporaries on any exception
  const TemporaryOutputs outputs = AddOutputs(options, !result.speech.audio.empty(), set, &log);
  try {
    RenderAndWrite(rig, options, outputs, &result, log);
    ThrowIfStopped();
  } catch (const Interrupted&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(set.WithFinalPaths(e.what()) + "; the previous outputs are unchanged");
  }
  set.Commit();  // signals are not checked from here on: the set goes in place whole
  result.mp4_written = !outputs.mp4.empty();
  return result;
}

void CheckHeadlessOutputs(const PlayerOptions& options) {
  OutputSet set;  // its temporaries go with it
  const bool may_speak = !options.say.empty() || !options.audio.empty() || !options.track.empty();
  AddOutputs(options, may_speak, set, nullptr);
}

Image RenderNeutral(const Rig& rig, int width, int height) {
  HeadlessGlContext context;
  IdleLifeParams idle;
  idle.head_motion = idle.saccades = false;
  FaceAnimator animator(rig, idle);
  animator.SetNeutral();
  FaceRenderer renderer(rig);
  OffscreenTarget target(width, height);
  renderer.Upload(animator.positions(), animator.normals());
  target.Bind();
  renderer.Draw(width, height, animator.head_rotation());
  Image image;
  target.Read(&image);
  return image;
}

}  // namespace facerig::player
