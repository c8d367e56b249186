#!/usr/bin/env bash
# The test command: installs what is missing, builds (warnings are errors) and
# runs every test. Tests needing ../shared/data carry the ctest label shared-data.
#   scripts/run-tests.sh [extra ctest arguments, e.g. -LE shared-data]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --tests
build=${FACERIG_BUILD_DIR:-build}
# nproc counts OMP_NUM_THREADS as the core count: ask without it (set below).
cores=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFACERIG_WARNINGS_AS_ERRORS=ON \
  ${FACERIG_CMAKE_ARGS:-}
# FACERIG_BUILD_TARGETS (space-separated): build only these (CI's sanitizer
# stage builds the test binaries, not the benchmark tool).
cmake --build "$build" -j "$cores" ${FACERIG_BUILD_TARGETS:+--target $FACERIG_BUILD_TARGETS}
# ctest runs one test per core: CHOLMOD's BLAS and OpenMP threads would then
# wait for cores the other tests hold (spinning), and a registration test took
# 36-50 s instead of 5-6 s on a loaded 2-core machine. One thread each.
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1} OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
ctest --test-dir "$build" -j "$cores" --output-on-failure "$@"
