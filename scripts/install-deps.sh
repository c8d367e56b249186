#!/usr/bin/env bash
# Installs the Debian 12 packages facerig needs that are missing, and the
# Khronos glTF validator and three.js with puppeteer-core (npm) used by the
# tests. Safe to run repeatedly.
#   scripts/install-deps.sh [--tests]   (--tests: also what only the tests need and is slow
#                                        to install; scripts/run-tests.sh passes it)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config
  libglm-dev libtinygltf-dev nlohmann-json3-dev   # runtime
  libeigen3-dev                                    # offline
  libsuitesparse-dev                               # offline: CHOLMOD sparse Cholesky (registration)
  libopenblas0-pthread                             # offline: BLAS for CHOLMOD's supernodal factorization
  libcli11-dev                                     # tools: one option parser (facerig, facerig-bench, player)
  libopencv-dev libdlib-dev libdlib-data           # offline: images, renders, the 68-point landmarks
  libpng-dev libjpeg62-turbo-dev                   # offline: PNG and JPEG bytes (io/image_codec.h)
  libxxhash-dev                                    # offline: the template cache's content key (BSD-2)
  opencv-data                                      # offline: the photo's second face detector (Haar cascade)
  libespeak-ng-dev espeak-ng-data                  # facerig::espeak (phoneme source)
  # runtime_io: recordings to align (WAV/FLAC/Ogg... via libsndfile, LGPL-2.1)
  # brought to the reference's sample rate (libsamplerate, BSD-2)
  libsndfile1-dev libsamplerate0-dev
  pocketsphinx-testdata                            # recorded English + transcripts: bench align/av-sync, av-sync test
  parallel                                         # scripts/build-cast.sh: a cast's builds over cores and machines
  # facerig-player: SDL2 window + audio; libepoxy loads GL for GLX/SDL and EGL
  # contexts alike, so the windowed and headless paths share one loader;
  # EGL + Mesa (llvmpipe) render headless without a display or GPU.
  libsdl2-dev libepoxy-dev libegl-dev libgl1-mesa-dri libegl-mesa0
  catch2                                           # tests
  libmeshoptimizer-dev                             # tests: decimated targets
  # real photographs for the photo tests: astronaut.png (NASA, public domain), camera.png (grey)
  python3-skimage
  # the C ABI's bindings, tested with Debian's interpreters (hosts/python, hosts/csharp)
  python3-numpy python3-pytest mono-mcs mono-runtime
  nodejs npm                                       # glTF validator in the tests
  chromium                                         # tests: written GLBs in three.js, headless (tests/browser)
  # the WebAssembly module (hosts/web, scripts/build-web.sh): emscripten 3.1.6
  # works offline; its JavaScript optimiser needs acorn (NODE_PATH=/usr/share/nodejs)
  emscripten node-acorn
)

# Only the test command needs these (scripts/run-main.sh does not wait for them).
test_packages=(
  # the Blender add-on's tests (hosts/blender, ctest label blender): Debian's Blender 3.4.1,
  # 49 packages, 98 MiB to download, 389 MiB installed, about 80 s to install
  blender
)
[[ ${1:-} == --tests ]] && packages+=("${test_packages[@]}")

missing=()
for package in "${packages[@]}"; do
  # nodejs from another source (e.g. NodeSource) is fine too.
  if [[ $package == nodejs || $package == npm ]] && command -v "${package/nodejs/node}" >/dev/null; then
    continue
  fi
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done

if ((${#missing[@]})); then
  echo "facerig: installing missing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

validator=tests/runtime/io/gltf_validator
if [[ ! -d $validator/node_modules/gltf-validator ]]; then
  echo "facerig: installing the Khronos glTF validator (npm ci in $validator)"
  npm ci --prefix "$validator" --no-audit --no-fund --loglevel=error
fi

web=hosts/web
if [[ ! -d $web/node_modules/three || ! -d $web/node_modules/puppeteer-core ]]; then
  echo "facerig: installing three.js, puppeteer-core and espeak-ng (WebAssembly) for the web page (npm ci in $web)"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error
fi

browser=tests/browser
if [[ ! -d $browser/node_modules/three || ! -d $browser/node_modules/puppeteer-core ]]; then
  echo "facerig: installing three.js and puppeteer-core for the browser test (npm ci in $browser)"
  npm ci --prefix "$browser" --no-audit --no-fund --loglevel=error
fi
