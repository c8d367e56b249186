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

namespace facerig::player {
namespace {

std::string FramePath(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%05d.png", index);
  return name;
}

void WriteMp4(const PlayerOptions& options, const std::filesystem::path& wav, std::ostream& log) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    log << "warning: --mp4 needs ffmpeg (Debian: ffmpeg); not written\n";
    return;
  }
  const auto quote = [](const std::filesystem::path& path) {
    std::string quoted = "'";
    for (char c : path.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
  };
  std::string command = "ffmpeg -loglevel error -y -framerate " + std::to_string(options.fps) + " -i " +
                        quote(options.frames_dir / "frame_%05d.png");
  if (!wav.empty()) command += " -itsoffset " + std::to_string(options.lead_in) + " -i " + quote(wav) + " -c:a aac";
  command += " -c:v libx264 -pix_fmt yuv420p " + quote(options.mp4);
  if (std::system(command.c_str()) != 0) throw std::runtime_error("ffmpeg failed: " + command);
  log << "wrote " << options.mp4.string() << '\n';
}

// The --emotion options, and the speech scheduled `options.lead_in` after frame 0.
void StartAnimation(const PlayerOptions& options, FaceAnimator* animator, HeadlessResult* result) {
  for (const auto& [emotion, intensity] : options.emotions) animator->character().SetEmotion(emotion, intensity);
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

// Frame i at time i / fps into options.frames_dir, with its timing and lip aperture.
void RenderFrames(const PlayerOptions& options, FaceAnimator& animator, FaceRenderer& renderer,
                  OffscreenTarget& target, Hud* hud, HeadlessResult* result) {
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
    const std::filesystem::path path = options.frames_dir / FramePath(frame);
    WritePng(path, image);
    result->frames.push_back(path);
  }
  result->samples = timer.samples();
  result->timing = timer.Summarize();
}

// --wav, and --mp4 (with the speech in a WAV next to it when there is no --wav).
void WriteSpeechAndVideo(const PlayerOptions& options, const SpeechLine& speech, std::ostream& log) {
  if (!options.wav.empty()) {
    WriteWav(options.wav, speech.audio, speech.sample_rate > 0 ? speech.sample_rate : EspeakPhonemeSource::kSampleRate);
  }
  if (!options.mp4.empty()) {
    std::filesystem::path wav = options.wav;
    if (wav.empty() && !speech.audio.empty()) {
      wav = options.mp4;
      wav.replace_extension(".wav");
      WriteWav(wav, speech.audio, speech.sample_rate);
    }
    WriteMp4(options, wav, log);
  }
}

}  // namespace

HeadlessResult RunHeadless(const Rig& rig, const PlayerOptions& options, std::ostream& log) {
  HeadlessResult result;
  if (!options.say.empty()) {
    EspeakPhonemeSource source;
    result.speech = source.Synthesize(options.say, options.voice);
  }
  std::error_code error;
  std::filesystem::create_directories(options.frames_dir, error);
  if (error) throw std::runtime_error("cannot create " + options.frames_dir.string() + ": " + error.message());

  HeadlessGlContext context;
  result.gl_description = context.description();
  IdleLifeParams idle;
  idle.head_motion = idle.saccades = !options.still;
  FaceAnimator animator(rig, idle);
  StartAnimation(options, &animator, &result);
  FaceRenderer renderer(rig);
  OffscreenTarget target(options.width, options.height, options.msaa);
  std::optional<Hud> hud;
  if (options.hud) hud.emplace();
  MeasureMouth(animator, renderer, options, &result);

  RenderFrames(options, animator, renderer, target, hud ? &*hud : nullptr, &result);
  WriteSpeechAndVideo(options, result.speech, log);
  return result;
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
