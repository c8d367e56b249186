// facerig-player: type text, the face speaks. See player_options.cpp for the
// command line. Links espeak-ng through facerig::espeak, so this program is GPL-3.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/rig_warnings.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/speech/phoneme_source.h"
#include "headless_player.h"
#include "player_options.h"
#include "recorded_speech.h"
#include "window_player.h"

namespace {

// "89352 samples at 22050 Hz, 4.052 s": what the WAV holds, the lead-in's silence included.
std::string WavSummary(const facerig::player::HeadlessResult& result) {
  char text[96];
  std::snprintf(text, sizeof text, "%zu samples at %d Hz, %.3f s", result.wav_samples, result.wav_rate,
                result.wav_rate > 0 ? static_cast<double>(result.wav_samples) / result.wav_rate : 0.0);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace facerig::player;
  PlayerOptions options;
  try {
    options = ParseOptions(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const UsageError& e) {
    std::cerr << "facerig-player: " << e.what() << "\nRun 'facerig-player --help' for the options.\n";
    return 2;
  }
  if (options.version) {
    std::cout << FACERIG_VERSION << '\n';
    return 0;
  }
  if (options.help) {
    std::cout << UsageText();
    return 0;
  }
  // Before loading anything: without a display, or with outputs that cannot be written, the answer is immediate.
  if (!options.headless) {
    if (const std::optional<std::string> message = NoDisplayMessage()) {
      std::cerr << *message << '\n';
      return 1;
    }
  }
  try {
    if (options.headless) {
      CheckHeadlessOutputs(options);
    } else {
      for (const std::filesystem::path& output : {options.screenshot, options.timing_json}) {
        if (!output.empty()) facerig::CheckOutputFolder(output);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "facerig-player: " << e.what() << '\n';
    return 1;
  }

  const std::filesystem::path rig_path = RigPath(options);
  std::optional<facerig::Rig> rig;
  try {
    rig = facerig::LoadRigOrTemplateFolder(rig_path);
  } catch (const std::exception& e) {
    std::cerr << "facerig-player: cannot load the rig " << rig_path.string() << ": " << e.what() << '\n';
    return 1;
  }
  const std::string rig_name = rig_path.filename().string();
  std::cout << "rig " << rig_path.string() << ": " << rig->vertex_count() << " vertices, " << rig->shape_count()
            << " shapes, " << rig->parts().size() << " parts\n";
  for (const facerig::RigWarning& warning : facerig::SpeechAndBlinkWarnings(*rig)) {
    std::cerr << "facerig-player: warning: " << warning.message << '\n';
  }

  if (WantsRoughMode(options)) {
    std::cerr << "facerig-player: no transcript: the rough mode, a coarse mouth from the audio alone "
                 "(give --text for lip-sync)\n";
  }
  try {
    if (!options.headless) return RunWindow(*rig, rig_name, options);
    InstallStopSignalHandlers();
    const HeadlessResult result = RunHeadless(*rig, options, std::cout);
    std::cout << "OpenGL: " << result.gl_description << '\n';
    std::cout << "wrote " << result.frames.size() << " frames (" << options.width << "x" << options.height << ", "
              << options.fps << " fps) to " << options.frames_dir.string() << '\n';
    if (!options.wav.empty()) std::cout << "wrote " << options.wav.string() << " (" << WavSummary(result) << ")\n";
    if (result.mp4_written) std::cout << "wrote " << options.mp4.string() << '\n';
    std::cout << FormatSummary(result.timing, "facerig-player --headless " + rig_name);
    if (!options.timing_json.empty()) std::cout << "wrote " << options.timing_json.string() << '\n';
    return 0;
  } catch (const Interrupted& e) {
    std::cerr << "facerig-player: " << e.what() << "; nothing written, the previous outputs are unchanged\n";
    return 128 + e.signal();
  } catch (const facerig::SpeechError& e) {
    std::cerr << "facerig-player: speech: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "facerig-player: " << e.what() << '\n';
    return 1;
  }
}
