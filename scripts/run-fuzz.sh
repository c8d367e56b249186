#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang into build-fuzz and runs each
# for SECONDS (default 60), starting from fuzz/seeds/<target>/; the corpus
# grows in build-fuzz/corpus/<target>/. Exits non-zero on the first finding
# (crash, sanitizer report, leak, timeout, or an exception other than IoError,
# or InvalidInputError for template descriptors);
# the input that caused it is left in build-fuzz/findings/.
#   scripts/run-fuzz.sh [SECONDS] [TARGET...]
#   (targets: gltf frig obj mtl image phoneme_track audio template landmarks photo capi)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf frig obj mtl image phoneme_track audio template landmarks photo capi)
build=${FACERIG_FUZZ_BUILD_DIR:-build-fuzz}

if ! command -v clang++ >/dev/null; then
  echo "run-fuzz.sh: clang++ is missing (apt-get install -y clang libclang-rt-14-dev)" >&2
  exit 2
fi
# -O1 with line tables (libFuzzer's usual flags): symbolised reports, and a
# cheaper compile than RelWithDebInfo's -O2 -g.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DFACERIG_FUZZ=ON -DFACERIG_BUILD_OFFLINE=OFF -DFACERIG_BUILD_ESPEAK=OFF -DFACERIG_BUILD_DEMO=OFF \
  -DFACERIG_BUILD_TESTS=OFF ${FACERIG_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "${FACERIG_FUZZ_JOBS:-$(nproc)}" --target "${targets[@]/%/_fuzzer}"

mkdir -p "$build/findings"
# One target's run; its log ends up in $build/findings/<target>.log.
run_target() {
  local target=$1 corpus="$build/corpus/$1" log="$build/findings/$1.log" status=0
  mkdir -p "$corpus"
  # -rss_limit_mb: a reader may allocate what the input's size justifies, not more.
  "$build/bin/${target}_fuzzer" "$corpus" "fuzz/seeds/$target" -max_total_time="$seconds" \
    -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/findings/${target}-" >"$log" 2>&1 || status=$?
  echo "$status" >"$build/findings/$target.status"
}

# The targets run side by side, one per core (each fuzzer is single-threaded).
jobs=${FACERIG_FUZZ_JOBS:-$(nproc)}
echo "== ${#targets[@]} targets x ${seconds} s, ${jobs} at a time"
for target in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  run_target "$target" &
done
wait

failed=0
for target in "${targets[@]}"; do
  echo "== $target"
  grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done [0-9]+ runs)" "$build/findings/$target.log" || true
  status=$(cat "$build/findings/$target.status")
  if [ "$status" -ne 0 ]; then
    tail -n 40 "$build/findings/$target.log" >&2
    echo "run-fuzz.sh: $target found a problem (exit $status); see $build/findings/" >&2
    failed=1
  fi
done
[ "$failed" -eq 0 ] || exit 1
echo "run-fuzz.sh: no findings in ${#targets[@]} targets x ${seconds} s"
