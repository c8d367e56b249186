"""(shared data) An ICT-FaceKit identity imported from OBJ: Build Face Shapes with the ICT-FaceKit
template writes its 67 shapes (all 52 ARKit, tongueOut made from ICT's tongue, and 15 visemes) and a Basis, 68 keys,
on the object itself: vertex count, UVs, materials, a modifier and the user's own shape key are
unchanged, and eyeBlinkLeft closes the left eye (seen from the front, the lids come to hide the left iris). Then
'Peter picked a peck of pickled peppers.' baked at 30 fps closes the lips at every p/b/m.
    ... --python ict_identity.py [-- --render OUT.png]   (also renders a frame of it speaking)"""
import os
import sys
from importlib import import_module

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402
from helpers import log  # noqa: E402

LINE = "Peter picked a peck of pickled peppers."
ICT = os.environ["FACERIG_ICT_DIR"]

addon = helpers.load_addon()
tts = import_module(addon.library.facerig().__name__ + ".tts")
helpers.empty_scene()
bpy.ops.wm.obj_import(filepath=os.path.join(ICT, "identity005.obj"))
face = bpy.context.selected_objects[0]
helpers.select_only(face)
mesh = face.data


def uvs():
    values = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", values)
    return values


before = {"vertices": len(mesh.vertices), "polygons": len(mesh.polygons), "uvs": uvs(),
          "materials": [slot.material.name for slot in face.material_slots],
          "rest": helpers.world_positions(face, evaluated=False)}
face.modifiers.new("Subdivision", "SUBSURF").levels = 1
face.shape_key_add(name="Basis", from_mix=False)
mine = face.shape_key_add(name="MyKey", from_mix=False)
mine.data[0].co.z += 1.0
assert before["vertices"] == 26719

assert bpy.ops.facerig.build_shapes(template="ICT", template_folder=ICT) == {"FINISHED"}
keys = mesh.shape_keys.key_blocks
facerig_keys = [k.name for k in keys if k.name not in ("Basis", "MyKey")]
assert len(facerig_keys) == 67 and len(keys) == 69, len(keys)  # + Basis = 68, + the user's own
assert sum(name.startswith("viseme_") for name in facerig_keys) == 15 and "tongueOut" in facerig_keys
assert len(mesh.vertices) == before["vertices"] and len(mesh.polygons) == before["polygons"]
assert np.array_equal(uvs(), before["uvs"])
assert [slot.material.name for slot in face.material_slots] == before["materials"]
assert [(m.name, m.type, m.levels) for m in face.modifiers] == [("Subdivision", "SUBSURF", 1)]
assert np.array_equal(helpers.world_positions(face, evaluated=False), before["rest"])
assert keys["MyKey"].data[0].co.z == keys["Basis"].data[0].co.z + 1.0
log(f"{len(keys)} keys: Basis, MyKey and {len(facerig_keys)} from ICT-FaceKit; "
    f"{len(mesh.vertices)} vertices, {len(mesh.loops)} UVs, {len(face.material_slots)} materials unchanged")

# eyeBlinkLeft: the character's left eye is on +X (the face looks toward -Y).
rest = before["rest"]
blink = helpers.key_positions(face, "eyeBlinkLeft")
moved = np.linalg.norm(blink - rest, axis=1)
assert moved[rest[:, 0] < 0].max() < 0.01 * moved.max(), "eyeBlinkLeft moves the right side"
skin = helpers.material_triangles(face, "M_Face")


def iris_front(material):
    iris = np.unique(helpers.material_triangles(face, material))
    return iris[rest[iris, 1] < np.median(rest[iris, 1])]  # the half toward the front (-Y)


left_iris, right_iris = iris_front("M_IrisLeft"), iris_front("M_IrisRight")
assert rest[left_iris, 0].min() > 0 > rest[right_iris, 0].max()
open_left = helpers.covered_fraction(rest[left_iris], skin, rest)
shut_left = helpers.covered_fraction(blink[left_iris], skin, blink)
open_right = helpers.covered_fraction(rest[right_iris], skin, rest)
shut_right = helpers.covered_fraction(blink[right_iris], skin, blink)
assert open_left < 0.5 and shut_left > 0.95 and shut_right == open_right, (open_left, shut_left, open_right, shut_right)
log(f"eyeBlinkLeft: the lids hide {100 * open_left:.0f}% of the left iris at rest, {100 * shut_left:.0f}% "
    f"blinking (the right iris: {100 * open_right:.0f}% both times); the upper lid moves {moved.max():.2f}")

# Peter picked a peck of pickled peppers, at 30 fps from frame 1 (measured without the modifier,
# on the mesh's own vertices).
face.modifiers.remove(face.modifiers["Subdivision"])
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = 30, 1.0
scene.frame_set(1)
assert bpy.ops.facerig.speak(text=LINE, voice="en-us") == {"FINISHED"}
phonemes = tts.synthesize(LINE, "en-us").phonemes
first, last = helpers.bake_range(face)
strip = helpers.sound_strip(face["facerig"]["bake"]["strip"])
assert strip.frame_start == first == 1
assert helpers.check_bilabials_close(face, phonemes, 1, 30) >= 6
log(f"baked frames {first:.0f}-{last:.0f}, sound strip at frame {strip.frame_start}")

if "--render" in sys.argv:
    out = sys.argv[sys.argv.index("--render") + 1]
    import render
    render.speaking_frame(face, phonemes, 1, 30, out)
    log(f"rendered {out}")
