// Command line of facerig-player.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "facerig/runtime/behaviour/emotion.h"

namespace facerig::player {

// A bad command line; the message says what is wrong (main prints it with the usage).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PlayerOptions {
  std::filesystem::path rig;  // empty: DefaultRigPath()
  std::string say;            // spoken at start
  std::string voice = "en-us";
  // A recording to speak instead of synthesized text: --audio with its
  // transcript (--text, aligned at start) or with --track (a phoneme track;
  // --audio may then be left out when the track names its audio), or alone
  // (the rough mode: a coarse mouth from the audio, RoughMouthFromAudio).
  std::filesystem::path audio;
  std::string text;
  std::filesystem::path track;
  std::vector<std::pair<Emotion, float>> emotions;  // --emotion joy[:0.8]
  bool still = false;         // no idle head motion or saccades (blinks stay)
  // Every normal recomputed from the triangles each frame (the blend before
  // kBlendRecomputedDeltas: the same picture, slower), for comparisons.
  bool recomputed_normals = false;
  bool hud = false;           // headless: draw the HUD into the frames (always on in the window)
  std::filesystem::path timing_json;
  // Window: quit after this many seconds (0: run until closed), saving the
  // last frame to `screenshot` if set (for tests and CI under Xvfb).
  double quit_after = 0.0;
  std::filesystem::path screenshot;

  bool headless = false;
  std::filesystem::path frames_dir;
  std::filesystem::path wav;
  std::filesystem::path mp4;
  double fps = 30.0;
  int width = 640, height = 480;
  // Multisample anti-aliasing samples (0: off). On Mesa llvmpipe 4x costs
  // ~2.5x the draw time of no MSAA.
  int msaa = 4;
  // The camera turned about the head from the front: yaw positive towards
  // the face's left (the camera moves towards +X), pitch positive from above.
  float yaw_degrees = 0.0f;
  float pitch_degrees = 0.0f;
  std::optional<double> duration;  // seconds; default: lead-in + speech + 0.6 s (at least 1 s)
  // Headless: the speech audio starts this long after frame 0, so the face
  // starts at rest and the mouth can move ahead of the sound (coarticulation
  // anticipates the first phoneme by up to ~0.2 s).
  double lead_in = 0.3;
  bool help = false;
  bool version = false;  // --version: print it and exit
};

// Throws UsageError.
PlayerOptions ParseOptions(const std::vector<std::string>& args);
// --help: generated from the options' definitions (each with its description).
std::string UsageText();
// The options defined without a description (for the test that there are none).
std::vector<std::string> OptionsWithoutDescription();

// The built-in head installed beside the player (BINDIR/../share/facerig/default_head.frig, found
// from the running executable, so an installed tree works from any folder), else the one the build
// generates (build/data/default_head.frig) for a player run from the build tree, else the
// ICT-FaceKit folder under the shared data directory.
std::filesystem::path DefaultRigPath();
// DefaultRigPath() for the player at `executable` (empty: not known).
std::filesystem::path DefaultRigPath(const std::filesystem::path& executable);
// options.rig, else DefaultRigPath().
std::filesystem::path RigPath(const PlayerOptions& options);

}  // namespace facerig::player
