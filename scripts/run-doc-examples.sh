#!/usr/bin/env bash
# Runs every command example of README.md and docs/*.md against the built
# programs, so that the documentation cannot drift from the tools.
#
#   scripts/run-doc-examples.sh [--list] [FILE.md...]
#
# An example is a fenced block opened with ```sh. A block opened with
# ```sh no-run is shown to readers but not run (set-up commands that install
# packages, windowed player runs, benchmarks that take minutes, commands that
# write into the repository); blocks in other languages (cpp, cmake, json, a
# bare ```) are not commands. Lines ending in '\' continue on the next line;
# blank lines and lines starting with '#' are skipped.
#
# Each Markdown file's examples run in order, each command in its own shell,
# in a fresh folder laid out like the repository root: build/bin links to the
# built programs, build/data and data/ are copies (an example cannot change
# the repository), and ../shared links to the shared data beside the
# repository, so the examples run exactly as written from the repository root.
# A block stops at its first failing command (later ones usually need its
# output); the script goes on with the next block and exits 1 if any command
# exited non-zero (or ran longer than FACERIG_DOC_EXAMPLE_TIMEOUT seconds,
# default 600). The work folder is removed unless something failed or
# FACERIG_DOC_EXAMPLES_KEEP=1.
#
# Environment: FACERIG_BUILD_DIR (default build), the build holding bin/ and data/.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${FACERIG_BUILD_DIR:-build}
[[ $build = /* ]] || build="$repo/$build"
timeout_seconds=${FACERIG_DOC_EXAMPLE_TIMEOUT:-600}

list_only=0
if [[ ${1:-} == --list ]]; then list_only=1; shift; fi
if (($# > 0)); then
  files=("$@")
else
  files=("$repo/README.md" "$repo"/docs/*.md)
fi

# Prints the runnable commands of one Markdown file as
# "BLOCK<TAB>LINE<TAB>COMMAND", continuation lines joined, one per line.
extract_commands() {
  awk '
    function flush() { if (command != "") print block "\t" start "\t" command; command = "" }
    /^```/ {
      if (!in_block) {
        in_block = 1
        block++
        info = substr($0, 4)
        run = (info ~ /^sh([ \t]|$)/) && (info !~ /(^|[ \t])no-run([ \t]|$)/)
      } else {
        flush(); in_block = 0; run = 0
      }
      next
    }
    !in_block || !run { next }
    {
      line = $0
      if (command == "") {
        if (line ~ /^[ \t]*(#|$)/) next
        start = NR
      }
      continued = sub(/\\[ \t]*$/, "", line)
      command = command line
      if (!continued) flush()
    }
    END { flush() }
  ' "$1"
}

if ((list_only)); then
  for file in "${files[@]}"; do
    while IFS=$'\t' read -r block line command; do
      printf '%s:%s: %s\n' "${file#"$repo"/}" "$line" "$command"
    done < <(extract_commands "$file")
  done
  exit 0
fi

for program in facerig facerig-player facerig-bench; do
  if [[ ! -x $build/bin/$program ]]; then
    echo "run-doc-examples: $build/bin/$program not found: build it first (cmake --build $build)" >&2
    exit 1
  fi
done
if [[ ! -e $build/data/default_head.frig ]]; then
  echo "run-doc-examples: $build/data/default_head.frig not found: the build generates it" >&2
  exit 1
fi
shared=$(cd "$repo/.." && pwd)/shared

work=$(mktemp -d "${TMPDIR:-/tmp}/facerig-doc-examples.XXXXXX")
failures=0
commands_run=0
for file in "${files[@]}"; do
  name=$(basename "$file" .md)
  root="$work/$name/repo"
  mkdir -p "$root/build"
  ln -s "$build/bin" "$root/build/bin"
  cp -r "$build/data" "$root/build/data"
  cp -r "$repo/data" "$root/data"
  [[ -e $shared ]] && ln -s "$shared" "$work/$name/shared"
  failed_block=0
  while IFS=$'\t' read -r block line command; do
    ((block == failed_block)) && continue
    where="${file#"$repo"/}:$line"
    echo "==> $where: $command"
    commands_run=$((commands_run + 1))
    started=$SECONDS
    (cd "$root" && timeout "$timeout_seconds" bash -o pipefail -c "$command") > "$work/$name/last.log" 2>&1
    status=$?
    echo "    ($((SECONDS - started)) s)"
    if ((status != 0)); then
      tail -n 30 "$work/$name/last.log" | sed 's/^/    /'
      echo "FAILED (exit $status): $where" >&2
      failures=$((failures + 1))
      failed_block=$block
    fi
  done < <(extract_commands "$file")
done

if ((failures > 0)); then
  echo "run-doc-examples: $failures example(s) failed ($commands_run commands run); work folder kept: $work" >&2
  exit 1
fi
echo "run-doc-examples: all $commands_run commands passed"
if [[ ${FACERIG_DOC_EXAMPLES_KEEP:-0} == 1 ]]; then
  echo "work folder: $work"
else
  rm -rf "$work"
fi
