#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs facerig-player on
# the built-in default head (data/default_head.frig; the ICT-FaceKit rig when
# it is missing) saying a sentence. Without a display ($DISPLAY and
# $WAYLAND_DISPLAY empty) it renders headless and says where the frames are.
# Usage: scripts/run-main.sh [RIG] [TEXT]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
build=${FACERIG_BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)" --target facerig-player

rig=${1:-data/default_head.frig}
if [[ ! -e $rig ]]; then
  echo "run-main: $rig not found; using the ICT-FaceKit rig" >&2
  rig=../shared/data/ict-facekit
fi
text=${2:-"Hello! I am a talking face. Type a line and I will say it."}
player="$build/demo/facerig-player"

if [[ -z ${DISPLAY:-} && -z ${WAYLAND_DISPLAY:-} ]]; then
  frames="$build/player_frames"
  rm -rf "$frames"
  "$player" --headless --rig "$rig" --say "$text" --frames "$frames" --wav "$build/player.wav" \
    --size 640x480 --fps 30 --hud --timing "$build/player_timing.json"
  echo
  echo "run-main: no display, so the player ran headless."
  echo "  frames: $frames/frame_00000.png ... ($(ls "$frames" | wc -l) PNGs, 30 fps)"
  echo "  audio:  $build/player.wav (starts 0.3 s after frame 0)"
  echo "  timing: $build/player_timing.json"
  if command -v ffmpeg >/dev/null; then
    echo "  video:  add --mp4 FILE to the player's command line to mux them (ffmpeg is installed)"
  fi
else
  "$player" --rig "$rig" --say "$text" --timing "$build/player_timing.json"
fi
