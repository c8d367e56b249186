// The interactive player: SDL2 window with an OpenGL 3.3 core context, a
// text line that speaks through espeak-ng and SDL2 audio, emotions, HUD.
#pragma once

#include <optional>
#include <string>

#include "facerig/runtime/rig.h"
#include "player_options.h"

namespace facerig::player {

// The message to print when there is no display to open a window on (neither
// DISPLAY nor WAYLAND_DISPLAY set, and no SDL_VIDEODRIVER chosen), else nullopt.
std::optional<std::string> NoDisplayMessage();
// The same advice after SDL failed to open a window for `reason`.
std::string WindowFailedMessage(const std::string& reason);

// Runs until the window closes or Esc. Returns the process exit code.
int RunWindow(const Rig& rig, const std::string& rig_name, const PlayerOptions& options);

}  // namespace facerig::player
