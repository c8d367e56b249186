#!/usr/bin/env bash
# The test command: installs what is missing, builds (warnings are errors) and
# runs every test. Tests needing ../shared/data carry the ctest label shared-data.
#   scripts/run-tests.sh [extra ctest arguments, e.g. -LE shared-data]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
build=${FACERIG_BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFACERIG_WARNINGS_AS_ERRORS=ON \
  ${FACERIG_CMAKE_ARGS:-}
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" -j "$(nproc)" --output-on-failure "$@"
