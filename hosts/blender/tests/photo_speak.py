"""Head from Photo on the astronaut portrait, then 'Peter picked a peck of pickled peppers.' baked at
30 fps: the lips close at every p/b/m on the mesh Blender evaluates, the sound strip starts at the
first keyframe; a re-bake replaces the bake and nothing else; Clear takes out what the add-on added. Cancelled on its worker thread, Head from Photo makes nothing.
    ... --python photo_speak.py [-- --render OUT.png]   (also renders frames of it speaking)"""
import os
import sys
import time
from importlib import import_module

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402
from helpers import log  # noqa: E402

LINE = "Peter picked a peck of pickled peppers."

addon = helpers.load_addon()
facerig = addon.library.facerig()
helpers.empty_scene()
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = 30, 1.0

# As the UI runs it (a modal operator, which headless Blender cannot run): on a worker thread,
# cancelled (Esc) at the first stage it reports: the photo command stops, no object is made.
job = addon.photo.photo_job(os.environ["FACERIG_PORTRAIT"])
worker = addon.jobs.Worker(job)
while worker.running() and not worker.progress.stage:
    time.sleep(0.01)
cancelled_at = worker.status()
worker.cancel()
try:
    worker.result()
    raise AssertionError("the cancelled photo head finished")
except facerig.CancelledError:
    pass
job.cleanup()
assert len(bpy.data.objects) == 0
log(f"cancelled at '{cancelled_at}': no object")

# Head from Photo: a new textured object with the shapes.
result = bpy.ops.facerig.head_from_photo(filepath=os.environ["FACERIG_PORTRAIT"])
assert result == {"FINISHED"}, result
head = bpy.context.active_object
assert head.name == "astronaut head", head.name
keys = head.data.shape_keys.key_blocks
assert len(keys) == 68 and "eyeBlinkLeft" in keys and "viseme_PP" in keys, len(keys)  # Basis + 52 + 15
textures = [node.image for slot in head.material_slots for node in slot.material.node_tree.nodes
            if node.type == "TEX_IMAGE" and node.image is not None]
assert textures and all(image.packed_file is not None for image in textures), textures
log(f"'{head.name}': {len(head.data.vertices)} vertices, {len(keys)} shape keys, textures "
    f"{[image.name for image in textures]}")

# The sidebar panel draws every operator, Clear too once the head is facerig's, with the
# voice en-us by default.
drawn = helpers.draw_panel()
assert [d[1] for d in drawn if d[0] == "operator"] == ["facerig.build_shapes", "facerig.speak",
                                                       "facerig.head_from_photo", "facerig.clear", "facerig.clear"]
assert ("set", "facerig.speak", "voice", "en-us") in drawn, drawn

# The user's own shape key with a keyframe: no bake or clear may touch it.
head.shape_key_add(name="MyKey", from_mix=False)
keys["MyKey"].value = 0.25
keys["MyKey"].keyframe_insert("value", frame=300)

# Speak at frame 10.
scene.frame_set(10)
result = bpy.ops.facerig.speak(source="TEXT", text=LINE, voice="en-us", emotion="JOY", emotion_strength=0.5)
assert result == {"FINISHED"}, result
tts = import_module(facerig.__name__ + ".tts")
phonemes = tts.synthesize(LINE, "en-us").phonemes
assert sum(p.symbol in helpers.BILABIALS for p in phonemes) >= 6
first, last = helpers.bake_range(head)
strip = helpers.sound_strip(head["facerig"]["bake"]["strip"])
assert strip.frame_start == first == 10, (strip.frame_start, first)
assert abs(strip.frame_final_duration - (phonemes[-1].start + phonemes[-1].duration) * 30) < 10, strip.frame_final_duration
assert strip.sound.packed_file is not None
log(f"baked frames {first:.0f}-{last:.0f}; sound strip '{strip.name}' at frame {strip.frame_start}, "
    f"{strip.frame_final_duration} frames")
assert helpers.check_bilabials_close(head, phonemes, 10, 30) >= 6
bpy.context.scene.frame_set(int(first) + 3)
assert keys["mouthSmileLeft"].value > 0.1, keys["mouthSmileLeft"].value  # joy
if "--render" in sys.argv:
    import render
    render.speaking_frame(head, phonemes, 10, 30, sys.argv[sys.argv.index("--render") + 1], color="TEXTURE")
blinks = [head.data.shape_keys.animation_data.action.fcurves.find('key_blocks["eyeBlinkLeft"].value')]
assert max(p.co.y for p in blinks[0].keyframe_points) > 0.8, "no blink"

# Re-bake at frame 100 with another line: the first bake's keys and strip go, MyKey's stay.
action = head.data.shape_keys.animation_data.action
result = bpy.ops.facerig.speak(source="TEXT", text="Bob bought a map.", use_current_frame=False, start_frame=100)
assert result == {"FINISHED"}, result
for fcurve in action.fcurves:
    frames = [p.co.x for p in fcurve.keyframe_points]
    if fcurve.data_path == 'key_blocks["MyKey"].value':
        assert frames == [300.0], frames
    else:
        assert min(frames) == 100 and max(frames) < 200, (fcurve.data_path, min(frames), max(frames))
strips = list(scene.sequence_editor.sequences_all)
assert len(strips) == 1 and strips[0].frame_start == 100, [(s.name, s.frame_start) for s in strips]
log("re-baked at frame 100: one strip, MyKey's keyframe at 300 kept")

# Clear the bake, then everything.
assert bpy.ops.facerig.clear(what="BAKE") == {"FINISHED"}
assert [fc.data_path for fc in action.fcurves] == ['key_blocks["MyKey"].value']
assert len(scene.sequence_editor.sequences_all) == 0
assert not any(sound.users for sound in bpy.data.sounds)
assert bpy.ops.facerig.clear(what="ALL") == {"FINISHED"}
assert [k.name for k in head.data.shape_keys.key_blocks] == ["Basis", "MyKey"], list(head.data.shape_keys.key_blocks.keys())
assert "facerig" not in head or "shapes" not in head["facerig"]
log("cleared: MyKey and its keyframe are all that is left")
