#!/usr/bin/env bash
# scripts/build-cast.sh on this machine (GNU parallel, 2 jobs, chunks of 2):
# three ICT identities and an unreadable face. The bad face is reported and
# the others built; run again after deleting one rig, only that face is
# built again; after a run killed in the middle of writing a face, the next
# run builds that face and nothing else, and no temporary is left.
#   tests/scripts/build_cast_test.sh FACERIG ICT_DIR WORK_DIR
set -euo pipefail
facerig=$1 ict=$2 work=$3
script="$(cd "$(dirname "$0")/../.." && pwd)/scripts/build-cast.sh"

fail() { echo "FAILED: $*" >&2; exit 1; }
# The value of a Python expression over the JSON file $1 (as `j`).
json() { python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($2)" "$1"; }
cast() { "$script" --template "$ict" --input "$work/faces" --output-dir "$work/out" --chunk 2 --jobs 2 \
           --facerig "$facerig"; }

rm -rf "$work" && mkdir -p "$work/faces"
for face in identity000 identity007 identity011; do cp "$ict/$face.obj" "$work/faces/"; done
printf 'v 1 2\nf 1 2 3 4\n' >"$work/faces/broken.obj"

echo "--- first run: 3 faces built, 1 failed (exit 3)"
status=0; cast || status=$?
((status == 3)) || fail "first run exited $status, expected 3 (some failed)"
[[ $(json "$work/out/cast.json" 'j["built"], j["failed"], j["missing"]') == "3 1 0" ]] || fail "cast.json counts"
[[ $(json "$work/out/cast.json" '[t["status"] for t in j["targets"]]') == "['failed', 'built', 'built', 'built']" ]] ||
  fail "cast.json statuses"
json "$work/out/cast.json" 'j["targets"][0]["error"]' | grep -q "broken.obj" || fail "the bad face's error names it"
for face in identity000 identity007 identity011; do
  [[ $(json "$work/out/$face.json" 'j["result"]["status"]') == built ]] || fail "$face's report"
  [[ -s $work/out/$face.glb ]] || fail "$face.glb"
  cp "$work/out/$face.json" "$work/$face.first.json"
done

echo "--- second run after deleting identity007.glb: only identity007 (and the failed face) again"
rm "$work/out/identity007.glb"
status=0; cast || status=$?
((status == 3)) || fail "second run exited $status, expected 3 (broken.obj still fails)"
cmp -s "$work/out/identity000.json" "$work/identity000.first.json" || fail "identity000 was built again"
cmp -s "$work/out/identity011.json" "$work/identity011.first.json" || fail "identity011 was built again"
cmp -s "$work/out/identity007.json" "$work/identity007.first.json" && fail "identity007 was not built again"
[[ -s $work/out/identity007.glb ]] || fail "identity007.glb not made again"

echo "--- a run killed while writing identity011 (SIGKILL after its rig): resumed by the next run"
rm "$work/out/identity011.json"
status=0; FACERIG_INJECT_FAILURE=kill-after-rig cast || status=$?
((status == 1)) || fail "the killed run exited $status, expected 1 (a face without a report)"
[[ ! -e $work/out/identity011.json ]] || fail "the killed run left a report"
[[ $(json "$work/out/cast.json" '[t["status"] for t in j["targets"]][3]') == missing ]] || fail "identity011 missing"
cp "$work/out/identity007.json" "$work/identity007.second.json"
status=0; cast || status=$?
((status == 3)) || fail "the resumed run exited $status, expected 3"
[[ $(json "$work/out/identity011.json" 'j["result"]["status"]') == built ]] || fail "identity011 not resumed"
cmp -s "$work/out/identity000.json" "$work/identity000.first.json" || fail "identity000 was built again"
cmp -s "$work/out/identity007.json" "$work/identity007.second.json" || fail "identity007 was built again"
[[ $(json "$work/out/cast.json" 'j["built"], j["failed"], j["missing"]') == "3 1 0" ]] || fail "final counts"
if ls -A "$work/out" | grep -q '^\.facerig-tmp'; then fail "temporaries left: $(ls -A "$work/out")"; fi
echo "build-cast.sh: all checks passed"
