#!/usr/bin/env bash
# The main job: installs what is missing, builds, and loads the ICT-FaceKit
# template rig (or, without ../shared/data, the committed reference rig),
# prints it and converts it to .glb and .frig under build/.
# (Until the player exists, this is the rig tool; see README.)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
build=${FACERIG_BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)" --target facerig
rig=${1:-../shared/data/ict-facekit}
[[ -e $rig ]] || rig=tests/runtime/io/data/reference_v1.frig
"$build/offline/facerig" inspect "$rig"
"$build/offline/facerig" convert "$rig" "$build/rig.glb"
"$build/offline/facerig" convert "$rig" "$build/rig.frig"
