"""Build Face Shapes with the built-in head as template on a head whose eyes and teeth are objects of
their own (the built-in head's neutral OBJ, imported and separated by material): the face gets every
shape, the eyes and teeth the shapes that move them (the eyes turn with eyeLookUpLeft, the lower teeth
drop with jawOpen); a mesh inside the head left unselected is named in the report. The build runs on
a worker thread as the UI runs it, reporting its stages to the polling main thread."""
import os
import shutil
import sys
import tempfile
import time
from importlib import import_module

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402
from helpers import log  # noqa: E402

addon = helpers.load_addon()
offline = import_module(addon.library.facerig().__name__ + ".offline")
helpers.empty_scene()
scratch = tempfile.mkdtemp(prefix="facerig-blender-test-")

# The built-in head made by the add-on's own call (into Blender's user data folder), then its
# neutral as an OBJ, imported and split into skin, eye, teeth, tongue and mouth_inner objects.
frig = addon.templates.builtin_head()(lambda stage, done, total: False)
obj_path = os.path.join(scratch, "head.obj")
offline.convert(frig, obj_path, neutral_only=True)
bpy.ops.wm.obj_import(filepath=obj_path)
imported = bpy.context.selected_objects[0]
vertex_total = len(imported.data.vertices)
helpers.select_only(imported)
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.separate(type="MATERIAL")
bpy.ops.object.mode_set(mode="OBJECT")
parts = {obj.active_material.name: obj for obj in bpy.data.objects if obj.type == "MESH"}
for name, obj in parts.items():
    obj.name = name
assert set(parts) == {"skin", "eye", "teeth", "tongue", "mouth_inner"}, set(parts)
assert sum(len(obj.data.vertices) for obj in parts.values()) == vertex_total
log(f"head split into {', '.join(f'{name} ({len(obj.data.vertices)})' for name, obj in parts.items())}")

# Build on the skin (active) with the eyes, teeth and inner mouth; the tongue left out.
helpers.select_only(parts["skin"], parts["eye"], parts["teeth"], parts["mouth_inner"])
rest = {name: helpers.world_positions(obj, evaluated=False) for name, obj in parts.items()}

# As the UI runs it (a modal operator, which headless Blender cannot run): on a worker thread, the
# main thread polling its status as the UI's timer does.
jobs = addon.jobs
job = addon.build.build_job(bpy.context, "BUILTIN")
worker = jobs.Worker(job)
statuses = []
while worker.running():
    statuses.append(worker.status())
    time.sleep(0.1)
message = job.apply(worker.result())
job.cleanup()
stages = list(dict.fromkeys(status.split(" - ")[1].split(" ")[0] for status in statuses if " - " in status))
assert {"register", "transfer", "map"} <= set(stages) and len(statuses) > 10, (stages, len(statuses))
assert any("(Esc to cancel)" in status and "/" in status for status in statuses)
log(f"built on a worker thread, {len(statuses)} polls, stages {stages}: {message}")
skin_keys = parts["skin"].data.shape_keys.key_blocks
assert len(skin_keys) == 68, len(skin_keys)
record = parts["skin"]["facerig"].to_dict()
assert record["parts"] == ["eye", "mouth_inner", "teeth"] and record["left_out"] == ["tongue"], record
assert parts["tongue"].data.shape_keys is None
for name in ("eye", "teeth", "mouth_inner"):
    assert np.array_equal(helpers.world_positions(parts[name], evaluated=False), rest[name])
eye_keys = parts["eye"].data.shape_keys.key_blocks
teeth_keys = parts["teeth"].data.shape_keys.key_blocks
assert "eyeLookUpLeft" in eye_keys and "jawOpen" not in eye_keys, list(eye_keys.keys())
assert "jawOpen" in teeth_keys and "eyeBlinkLeft" not in teeth_keys, list(teeth_keys.keys())
log(f"keys: skin {len(skin_keys)}, eye {len(eye_keys)}, teeth {len(teeth_keys)}, "
    f"mouth_inner {len(parts['mouth_inner'].data.shape_keys.key_blocks)}")

# The left eye (the character's left: +X, the face looking toward -Y) looks up; the right one stays.
eye_rest = rest["eye"]
looked = helpers.key_positions(parts["eye"], "eyeLookUpLeft")
left = eye_rest[:, 0] > 0
moved = np.linalg.norm(looked - eye_rest, axis=1)
front_left = left & (eye_rest[:, 1] < np.percentile(eye_rest[left, 1], 10))  # the cornea, in front
assert moved[~left].max() < 1e-6 and moved[left].max() > 0.01 * np.ptp(eye_rest[left], axis=0).max()
assert (looked[front_left, 2] - eye_rest[front_left, 2]).mean() > 0, "the left eye's front does not rise"

# jawOpen drops the lower teeth, keeps the upper ones.
teeth_rest = rest["teeth"]
opened = helpers.key_positions(parts["teeth"], "jawOpen")
drop = teeth_rest[:, 2] - opened[:, 2]
upper = teeth_rest[:, 2] > np.median(teeth_rest[:, 2])
assert drop[~upper].mean() > 10 * max(abs(drop[upper]).mean(), 1e-9), (drop[~upper].mean(), drop[upper].mean())
log(f"eyeLookUpLeft raises the left cornea {(looked[front_left, 2] - eye_rest[front_left, 2]).mean():.3f}; "
    f"jawOpen drops the lower teeth {drop[~upper].mean():.3f}, the upper {drop[upper].mean():.4f}")

# Speak drives the parts too; Clear takes the keys off all of them.
bpy.context.scene.frame_set(1)
helpers.select_only(parts["skin"])
assert bpy.ops.facerig.speak(text="Papa", blinks=False, gaze=False) == {"FINISHED"}
action = parts["teeth"].data.shape_keys.animation_data.action
assert action.fcurves.find('key_blocks["jawOpen"].value') is not None
assert bpy.ops.facerig.clear(what="ALL") == {"FINISHED"}
for name in ("skin", "eye", "teeth", "mouth_inner"):
    assert parts[name].data.shape_keys is None, name
    assert np.array_equal(helpers.world_positions(parts[name], evaluated=False), rest[name])
shutil.rmtree(scratch)
log("spoken on the face and its parts, then cleared from all of them")
