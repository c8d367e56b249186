#!/usr/bin/env python3
"""Per-frame cost through the Python binding, for `facerig-bench abi`.

abi_frames.py HEAD TRACK FRAMES REPEATS: a character speaks TRACK on HEAD;
FRAMES frames of Character.update (and of update + Rig.blend) into arrays
made once, the best of REPEATS runs; prints {"update_us": .., "update_blend_us": ..}
per frame as JSON.
"""
import json
import sys
import time

import numpy as np

import facerig


def best_per_frame(frames, repeats, frame):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        for i in range(frames):
            frame(i)
        best = min(best, (time.perf_counter() - start) / frames)
    return best * 1e6


def main():
    head, track, frames, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    rig = facerig.Rig(head)
    character = facerig.Character(rig)
    character.speak(facerig.Speech.from_track(track))
    weights = np.empty(rig.shape_count, np.float32)
    positions = np.empty((rig.vertex_count, 3), np.float32)
    period = 840  # 14 s of frames, the track's length

    def update(i):
        character.update((i % period) / 60.0, out=weights)

    def update_blend(i):
        character.update((i % period) / 60.0, out=weights)
        rig.blend(weights, out=positions)

    print(json.dumps({"update_us": best_per_frame(frames, repeats, update),
                      "update_blend_us": best_per_frame(max(frames // 10, 1), repeats, update_blend)}))


if __name__ == "__main__":
    main()
