"""What the native runtime gives, for the browser tests to compare the page with (libfacerig and
libfacerig_espeak through the Python package, found through FACERIG_LIBRARY_DIR):

    python3 native_reference.py weights HEAD.glb TRACK.json SEED FRAMES FPS OUT.json
        a character with SEED speaks the track from time 0, updated at frame / FPS for each frame:
        {"names": [rig shape names], "times": [...], "frames": [[weight per shape], ...]}
    python3 native_reference.py phonemes LINES.json OUT.json
        LINES.json is [[text, voice], ...]; OUT.json the native espeak-ng phoneme symbols of each
        line: [[symbol, ...], ...]
"""
import json
import sys

import facerig


def weights(head, track, seed, frames, fps, out):
    rig = facerig.Rig(head)
    character = facerig.Character(rig, seed=int(seed))
    with open(track, encoding="utf-8") as file:
        character.speak(facerig.Speech.from_track(file.read()), 0.0)
    times = [i / float(fps) for i in range(int(frames))]
    frames = [[float(w) for w in character.update(t)] for t in times]
    with open(out, "w", encoding="utf-8") as file:
        json.dump({"names": rig.shape_names, "times": times, "frames": frames}, file)


def phonemes(lines, out):
    import facerig.tts
    with open(lines, encoding="utf-8") as file:
        wanted = json.load(file)
    symbols = [[p.symbol for p in facerig.tts.synthesize(text, voice).phonemes] for text, voice in wanted]
    with open(out, "w", encoding="utf-8") as file:
        json.dump(symbols, file)


if __name__ == "__main__":
    commands = {"weights": (weights, 6), "phonemes": (phonemes, 2)}
    if len(sys.argv) < 2 or sys.argv[1] not in commands or len(sys.argv) != 2 + commands[sys.argv[1]][1]:
        sys.exit(__doc__)
    commands[sys.argv[1]][0](*sys.argv[2:])
