#!/usr/bin/env bash
# Builds a cast: every face in a folder, with `facerig build --output-dir` (the
# template's work done once per run), CHUNK faces per run, the runs spread by
# GNU parallel over this machine's cores or several machines (--sshlogin, as
# GNU parallel takes it; the machines must see the same paths, e.g. over NFS,
# and have facerig at the same path). Run it again after an interruption: a
# face whose report says "built" and whose rig is there is not built again.
# At the end the per-face reports are merged into OUT/cast.json.
#
#   scripts/build-cast.sh --template T --input DIR --output-dir OUT [--chunk N] [--jobs N]
#       [--sshlogin LOGIN]... [--facerig PATH] [-- more facerig build options]
#
# Exit codes: 0 every face built, 3 some failed (their errors in cast.json),
# 1 some faces have no report (a run was stopped: run the script again), 2 usage.
set -euo pipefail

usage() {
  sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

template="" input="" output="" chunk=10 jobs=1 format=glb
facerig="$(cd "$(dirname "$0")/.." && pwd)/build/bin/facerig"
[[ -x $facerig ]] || facerig=$(command -v facerig || true)
sshlogins=() extra=()
while (($#)); do
  case $1 in
    --template) template=$2; shift 2 ;;
    --input) input=$2; shift 2 ;;
    --output-dir) output=$2; shift 2 ;;
    --chunk) chunk=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --sshlogin) sshlogins+=(--sshlogin "$2"); shift 2 ;;
    --facerig) facerig=$2; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "build-cast.sh: unknown option '$1'" >&2; usage ;;
  esac
done
[[ -n $template && -n $input && -n $output ]] || usage
[[ $chunk =~ ^[1-9][0-9]*$ ]] || { echo "build-cast.sh: --chunk must be a positive number, got '$chunk'" >&2; exit 2; }
for ((i = 0; i < ${#extra[@]}; ++i)); do
  [[ ${extra[i]} == --format ]] && format=${extra[i + 1]:-glb}
done
[[ -x $facerig ]] || { echo "build-cast.sh: no facerig executable (build it, or pass --facerig PATH)" >&2; exit 2; }
command -v parallel >/dev/null || { echo "build-cast.sh: needs GNU parallel (Debian: apt install parallel)" >&2; exit 2; }
[[ -d $input ]] || { echo "build-cast.sh: --input $input is not a folder" >&2; exit 2; }
mkdir -p "$output"
# Absolute paths: the same on every machine that shares them.
template=$(realpath "$template") input=$(realpath "$input") output=$(realpath "$output") facerig=$(realpath "$facerig")

# The faces to build: every target file of the input folder whose report in
# OUT does not say "built" or whose rig is missing. Then the merge.
cast_py() {
  python3 - "$@" <<'PYTHON'
import json, os, sys

mode, input_dir, output_dir, rig_format = sys.argv[1:5]
faces = sorted(f for f in os.listdir(input_dir)
               if not f.startswith(".") and os.path.splitext(f)[1].lower() in (".obj", ".glb", ".gltf", ".frig")
               and os.path.isfile(os.path.join(input_dir, f)))

def report_of(face):
    name = os.path.splitext(face)[0]
    try:
        with open(os.path.join(output_dir, name + ".json")) as file:
            return name, json.load(file)
    except (OSError, ValueError):
        return name, None

def built(name, report):
    return (report is not None and report.get("result", {}).get("status") == "built"
            and os.path.isfile(os.path.join(output_dir, name + "." + rig_format)))

if mode == "pending":
    for face in faces:
        if not built(*report_of(face)):
            print(os.path.join(input_dir, face))
    sys.exit(0)

targets, counts = [], {"built": 0, "failed": 0, "missing": 0}
for face in faces:
    name, report = report_of(face)
    entry = {"name": name, "target": os.path.join(input_dir, face), "report": os.path.join(output_dir, name + ".json")}
    if built(name, report):
        entry.update(status="built", rig=os.path.join(output_dir, name + "." + rig_format),
                     seconds=report.get("timings", {}).get("total"),
                     residual_mean_percent=report["result"]["registration"]["residual_percent_of_diagonal"]["mean"])
    elif report is not None and report.get("result", {}).get("status") == "failed":
        entry.update(status="failed", error=report["result"].get("error", ""))
    else:
        entry.update(status="missing")  # never run, or stopped before its report
    counts[entry["status"]] += 1
    targets.append(entry)
summary = {"schema": 1, "command": "build-cast", "input": input_dir, "output_dir": output_dir, **counts,
           "targets": targets}
temporary = os.path.join(output_dir, ".cast.json.partial")
with open(temporary, "w") as file:
    json.dump(summary, file, indent=2)
    file.write("\n")
os.replace(temporary, os.path.join(output_dir, "cast.json"))
print(f"cast: {counts['built']} built, {counts['failed']} failed, {counts['missing']} missing of {len(faces)} "
      f"faces; summary {os.path.join(output_dir, 'cast.json')}")
for entry in targets:
    if entry["status"] == "failed":
        print(f"  failed: {entry['target']}: {entry['error']}")
sys.exit(1 if counts["missing"] else 3 if counts["failed"] else 0)
PYTHON
}

mapfile -t pending < <(cast_py pending "$input" "$output" "$format")
echo "build-cast.sh: ${#pending[@]} faces to build in $output (chunks of $chunk, $jobs jobs per machine)" >&2
if ((${#pending[@]})); then
  # Each job: one facerig run over up to $chunk faces (appended after --target).
  # A job whose faces partly failed exits 3: the merge below reports them.
  printf '%s\n' "${pending[@]}" |
    parallel -q --halt never -n "$chunk" -j "$jobs" "${sshlogins[@]}" \
      "$facerig" build --template "$template" --output-dir "$output" "${extra[@]}" --target || true
fi
cast_py merge "$input" "$output" "$format"
