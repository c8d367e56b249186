"""Speak from a recording: with its transcript (aligned) and alone (the rough mode), on the built-in
head imported from its GLB (shape keys facerig did not write: Speak drives any mesh with ARKit and
viseme keys); and bad inputs (a mesh that is not a face, a missing template folder, unreadable or
missing recordings, no text, an unknown voice, a photo without a face) each give a report and leave
the object as it was."""
import os
import shutil
import sys
import tempfile
from importlib import import_module

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402
from helpers import log  # noqa: E402

RECORDING = "/usr/share/pocketsphinx/test/data/librivox/sense_and_sensibility_01_austen_64kb-0930.wav"
TRANSCRIPT = "he might even have been made amiable himself"

addon = helpers.load_addon()
facerig = addon.library.facerig()
tts = import_module(facerig.__name__ + ".tts")
helpers.empty_scene()
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = 24, 1.0
scratch = tempfile.mkdtemp(prefix="facerig-blender-test-")

# The built-in head from its GLB: 67 shape keys of its own.
addon.photo.import_gltf(os.environ["FACERIG_DEFAULT_HEAD_GLB"])
head = max((o for o in bpy.data.objects if o.type == "MESH"), key=lambda o: len(o.data.vertices))
helpers.select_only(head)
assert "facerig" not in head and len(head.data.shape_keys.key_blocks) == 68

# A recording with its transcript, at 24 fps from frame 1.
scene.frame_set(1)
assert bpy.ops.facerig.speak(source="RECORDING", audio_path=RECORDING, transcript=TRANSCRIPT) == {"FINISHED"}
samples, rate = facerig.Speech.from_audio_file(RECORDING).audio
phonemes = tts.align(samples, rate, TRANSCRIPT, "en-us").phonemes
strip = helpers.sound_strip(head["facerig"]["bake"]["strip"])
assert strip.frame_start == helpers.bake_range(head)[0] == 1
assert os.path.samefile(bpy.path.abspath(strip.sound.filepath), RECORDING) and strip.sound.packed_file is None
assert helpers.check_bilabials_close(head, phonemes, 1, 24) >= 5
log(f"aligned recording: {len(phonemes)} phonemes, strip '{strip.name}' of {strip.frame_final_duration} frames")

# The same recording alone: the rough mode moves the mouth over the recording.
assert bpy.ops.facerig.speak(source="AUDIO", audio_path=RECORDING) == {"FINISHED"}
first, last = helpers.bake_range(head)
assert abs((last - first + 1) / 24 - (samples.size / rate + addon.speak.TAIL_SECONDS)) < 0.1
frames = range(int(first), int(last) + 1, 2)
aperture = helpers.apertures(head, frames)
assert aperture.max() > 3 * aperture[0], aperture
assert len(scene.sequence_editor.sequences_all) == 1
log(f"rough mode: frames {first:.0f}-{last:.0f}, aperture up to {aperture.max():.4f} from {aperture[0]:.4f}")

# Bad inputs on the head: each a report, nothing changed.
not_audio = os.path.join(scratch, "notes.wav")
with open(not_audio, "w") as out:
    out.write("not audio\n")
missing = os.path.join(scratch, "missing.wav")
speak = bpy.ops.facerig.speak
helpers.expect_report(speak, ["notes.wav"], head, source="AUDIO", audio_path=not_audio)
helpers.expect_report(speak, ["missing.wav"], head, source="RECORDING", audio_path=missing, transcript="hello")
helpers.expect_report(speak, ["text"], head, source="TEXT", text="  ")
helpers.expect_report(speak, ["transcript"], head, source="RECORDING", audio_path=RECORDING, transcript="")
helpers.expect_report(speak, ["voice", "en-us"], head, source="TEXT", text="Hello.", voice="xx-nope")
helpers.expect_report(bpy.ops.facerig.build_shapes, ["ict-nowhere", "does not exist"], head, template="ICT",
                      template_folder=os.path.join(scratch, "ict-nowhere"))

# A mesh that is not a face: no shapes, no keys.
bpy.ops.mesh.primitive_uv_sphere_add(radius=10.0)
ball = bpy.context.active_object
helpers.expect_report(speak, ["no ARKit", "Build Face Shapes"], ball, source="TEXT", text="Hello.")
helpers.expect_report(bpy.ops.facerig.build_shapes, ["face"], ball, template="BUILTIN")
assert ball.data.shape_keys is None

# A photo with no face in it: no new object.
objects = len(bpy.data.objects)
for photo, words in ((os.path.join(scratch, "none.png"), ["none.png", "does not exist"]),
                     (os.environ["FACERIG_NO_FACE_PHOTO"], ["face"])):
    helpers.expect_report(bpy.ops.facerig.head_from_photo, words, ball, filepath=photo)
assert len(bpy.data.objects) == objects

# Edit Mode: the operators are not available.
bpy.ops.object.mode_set(mode="EDIT")
helpers.expect_report(bpy.ops.facerig.build_shapes, ["poll"], ball, template="BUILTIN")
bpy.ops.object.mode_set(mode="OBJECT")
shutil.rmtree(scratch)
log("every bad input reported, nothing changed")
