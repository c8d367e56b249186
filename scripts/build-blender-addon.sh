#!/usr/bin/env bash
# The Blender add-on as one zip to install (Edit > Preferences > Add-ons > Install...):
# hosts/blender/facerig_blender with the Python package (hosts/python/facerig)
# and the built libraries libfacerig, libfacerig_espeak and libfacerig_offline
# inside it, facerig's ICT-FaceKit descriptor, and the licences.
#   scripts/build-blender-addon.sh [--no-build] [OUT_ZIP]   (default build/facerig_blender.zip)
# Builds the three libraries first (Release, in $FACERIG_BUILD_DIR or build/)
# unless --no-build. The libraries link Debian 12's shared libraries (OpenCV,
# dlib, CHOLMOD, espeak-ng, libsndfile...): see docs/blender.md.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FACERIG_BUILD_DIR:-build}
if [[ ${1:-} == --no-build ]]; then
  shift
else
  [[ -f $build/CMakeCache.txt ]] || cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j "$(nproc)" --target facerig_capi facerig_capi_espeak facerig_capi_offline
fi
out=$(realpath -m "${1:-$build/facerig_blender.zip}")
for library in libfacerig.so.0 libfacerig_espeak.so.0 libfacerig_offline.so.0; do
  [[ -e $build/lib/$library ]] || { echo "build-blender-addon: $build/lib/$library is missing (build it)" >&2; exit 1; }
done

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
addon=$stage/facerig_blender
cp -r hosts/blender/facerig_blender "$addon"
cp -r hosts/python/facerig "$addon/facerig"
cp -L "$build"/lib/libfacerig.so.0 "$build"/lib/libfacerig_espeak.so.0 "$build"/lib/libfacerig_offline.so.0 "$addon/facerig/"
mkdir -p "$addon/templates"
cp data/templates/ict-facekit.template.json "$addon/templates/"
cp LICENSE "$addon/LICENSE-facerig.txt"
cat > "$addon/LICENSES.txt" <<'TEXT'
The facerig Blender add-on, as this zip holds it:

- facerig_blender/*.py (the add-on) and facerig/*.py (facerig's Python package): MIT, LICENSE-facerig.txt.
- facerig/libfacerig.so.0: facerig's runtime (MIT), linking libsndfile (LGPL-2.1+) and
  libsamplerate (BSD-2-Clause) as shared libraries of the system.
- facerig/libfacerig_espeak.so.0: links espeak-ng (GPL-3.0): GPL-3 as a whole.
- facerig/libfacerig_offline.so.0: facerig's offline tools, linking CHOLMOD (GPL-2+ modules),
  espeak-ng (GPL-3.0), OpenCV (Apache-2.0), dlib (BSL-1.0): GPL-3 as a whole.

The zip as a whole is therefore GPL-3, as Blender add-ons are anyway. The libraries the .so files
link (Debian 12 packages) are not in the zip; docs/blender.md in facerig's repository lists them.
ICT-FaceKit is not included: point the add-on's preferences at your copy (its own licence).
TEXT
find "$addon" -name __pycache__ -prune -exec rm -rf {} +
mkdir -p "$(dirname "$out")"
rm -f "$out.tmp"
(cd "$stage" && python3 -c 'import shutil, sys; shutil.make_archive(sys.argv[1], "zip", ".", "facerig_blender")' "$out.tmp")
mv "$out.tmp.zip" "$out"
echo "wrote $out ($(du -k "$out" | cut -f1) KiB)"
