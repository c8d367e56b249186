#!/usr/bin/env bash
# The demo page on localhost: builds the WebAssembly module (scripts/build-web.sh),
# the built-in head if it is missing (build/, as scripts/run-tests.sh makes it),
# then serves the repository with a static HTTP server (node; it answers the
# Range requests with which the page fetches one language's espeak-ng data)
# and prints the page's address. Ctrl-C stops it.
#   scripts/run-web.sh [PORT]       (default 8080; FACERIG_BUILD_DIR: build/)
set -euo pipefail
cd "$(dirname "$0")/.."
port=${1:-8080}
build=${FACERIG_BUILD_DIR:-build}

if [[ ! -d hosts/web/node_modules/three || ! -d hosts/web/node_modules/@echogarden/espeak-ng-emscripten ]]; then
  echo "run-web: three.js and espeak-ng are missing from hosts/web/node_modules: run scripts/install-deps.sh" >&2
  exit 1
fi
scripts/build-web.sh
if [[ ! -f $build/data/default_head.glb ]]; then
  echo "run-web: making the built-in head ($build/data/default_head.glb)"
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j"${FACERIG_JOBS:-2}" --target facerig_default_head
fi
query=""
[[ $build != build ]] && query="?head=../../../$build/data/default_head.glb"
echo "run-web: serving $PWD on http://127.0.0.1:$port/ (Ctrl-C stops)"
exec node hosts/web/tests/serve.mjs "$port" "hosts/web/demo/index.html$query"
