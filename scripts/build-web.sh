#!/usr/bin/env bash
# Builds the WebAssembly module hosts/web/dist/facerig.mjs + facerig.wasm with
# Debian's emscripten (installed by scripts/install-deps.sh), in build-web/
# (FACERIG_WEB_BUILD_DIR to change it). Offline: no emscripten ports, no
# downloads. Prints the sizes (raw and gzipped) at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${FACERIG_WEB_BUILD_DIR:-build-web}

if ! command -v em++ >/dev/null || [[ ! -d /usr/share/nodejs/acorn ]]; then
  echo "build-web: Debian's emscripten and node-acorn are missing: run scripts/install-deps.sh" >&2
  exit 1
fi
# Emscripten's JavaScript optimiser imports acorn, which Debian installs under /usr/share/nodejs.
export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

emcmake cmake -S hosts/web -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build "$build_dir" -j"${FACERIG_JOBS:-2}"

for file in hosts/web/dist/facerig.mjs hosts/web/dist/facerig.wasm; do
  printf 'build-web: %-32s %8d bytes, %8d gzipped\n' "$file" "$(stat -c %s "$file")" "$(gzip -9c "$file" | wc -c)"
done
