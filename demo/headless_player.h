// --headless: offscreen frames at a fixed frame rate (animation time =
// frame / fps, so the output is deterministic), the speech as a WAV, and
// optionally an MP4 through ffmpeg. No window, no sound card.
#pragma once

#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/speech/phoneme.h"
#include "frame_timing.h"
#include "media_writer.h"
#include "player_options.h"

namespace facerig::player {

struct HeadlessResult {
  std::string gl_description;
  std::vector<std::filesystem::path> frames;  // frame i at time i / fps
  SpeechLine speech;                          // what was said (audio and phonemes); empty without --say or --audio
  double speech_start = 0.0;                  // animation time of the speech's first sample (lead-in)
  std::vector<float> lip_aperture;            // per frame, rig units (FaceAnimator::LipAperture)
  bool has_mouth = false;
  glm::vec2 mouth_pixel{0.0f};                // neutral mouth centre in the frames (x right, y down)
  float mouth_radius_pixels = 0.0f;           // about half the mouth width in pixels
  TimingSummary timing;
  std::vector<FrameSample> samples;
  std::size_t wav_samples = 0;  // in the WAV written: the lead-in's silence and the speech
  int wav_rate = 0;             // its sample rate
  bool mp4_written = false;     // false without ffmpeg
};

// A headless run stopped by SIGINT or SIGTERM: after InstallStopSignalHandlers()
// (output_set.h), RunHeadless checks after each frame and between its writes,
// removes its temporaries and throws Interrupted.
using facerig::InstallStopSignalHandlers;
using facerig::Interrupted;

// Synthesizes options.say (espeak-ng; SpeechError on a bad voice), or reads
// the recording of --audio / --track (recorded_speech.h), renders
// the frames into options.frames_dir, writes options.wav / .mp4 / .timing_json.
// The outputs are one set (OutputSet): written under temporary names and put in
// place together at the end (the frames folder is replaced, not merged); on any
// error or Interrupted nothing changes. Progress and warnings go to `log`.
// Throws std::runtime_error (and subclasses) naming the output's final path.
HeadlessResult RunHeadless(const Rig& rig, const PlayerOptions& options, std::ostream& log);

// Throws std::runtime_error (naming the path as given) when the outputs of
// `options` cannot be written as one set: a missing or unwritable folder, an
// output inside another (other than a file directly in the frames folder), a
// file named like a frame, a frames folder holding other files. Run before the
// rig is loaded and the speech made, so that nothing is rendered in vain.
void CheckHeadlessOutputs(const PlayerOptions& options);

// One frame of the rig at rest (all weights 0, no head motion), for tests.
Image RenderNeutral(const Rig& rig, int width, int height);

}  // namespace facerig::player
