"""Shared by the add-on's tests, which Blender runs headless:
    blender -b --factory-startup --python-exit-code 1 --python TEST.py
The add-on comes from the zip of scripts/build-blender-addon.sh when $FACERIG_BLENDER_ZIP names it
(installed into $BLENDER_USER_SCRIPTS, its bundled libraries only), else from the source tree
(hosts/blender, with $FACERIG_LIBRARY_DIR)."""
import os
import sys
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BILABIALS = {"p", "b", "m"}
_START = time.perf_counter()


def log(message):
    print(f"[{time.perf_counter() - _START:6.1f} s] {message}", flush=True)


def load_addon():
    """Installs and enables the add-on; returns its module."""
    zip_path = os.environ.get("FACERIG_BLENDER_ZIP")
    if zip_path:
        import addon_utils
        os.environ.pop("FACERIG_LIBRARY_DIR", None)  # the bundled libraries, nothing else
        bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
        module = addon_utils.enable("facerig_blender", default_set=True)
        assert module is not None, "the add-on did not enable (see the traceback above)"
        assert module.__file__.startswith(bpy.utils.user_resource("SCRIPTS")), module.__file__
    else:
        sys.path.insert(0, os.path.normpath(os.path.join(HERE, "..")))
        import facerig_blender as module
        module.register()
    log(f"add-on from {os.path.dirname(module.__file__)}")
    return module


def empty_scene():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    editor = bpy.context.scene.sequence_editor
    if editor:  # strip by strip: sequence_editor_clear() then a frame-rate change crashes Blender 3.4
        for strip in list(editor.sequences):
            editor.sequences.remove(strip)


def select_only(*objects):
    bpy.ops.object.select_all(action="DESELECT")
    for obj in objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]


def snapshot(obj):
    """What an operator that failed must leave as it was."""
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    keys = mesh.shape_keys
    return {"vertices": co, "polygons": len(mesh.polygons),
            "keys": [k.name for k in keys.key_blocks] if keys else [],
            "fcurves": (sum(len(fc.keyframe_points) for fc in keys.animation_data.action.fcurves)
                        if keys and keys.animation_data and keys.animation_data.action else 0),
            "record": obj["facerig"].to_dict() if "facerig" in obj else {},
            "strips": len(bpy.context.scene.sequence_editor.sequences_all) if bpy.context.scene.sequence_editor else 0}


def expect_report(operator, words, obj, **properties):
    """Runs the operator, which must fail with an error report containing `words` and leave obj as
    it was."""
    before = snapshot(obj)
    try:
        operator(**properties)
    except RuntimeError as error:  # how an operator's ERROR report reaches a script
        message = str(error)
    else:
        raise AssertionError(f"{operator.idname()} with {properties} did not fail")
    assert "Traceback" not in message, message
    for word in words:
        assert word.lower() in message.lower(), f"'{word}' not in the report: {message}"
    after = snapshot(obj)
    assert np.array_equal(before.pop("vertices"), after.pop("vertices")), "the vertices changed"
    assert before == after, f"{before} != {after}"
    log(f"reported: {message.strip()}")
    return message


def world_positions(obj, evaluated=True):
    """(n, 3) world positions: of the evaluated mesh (shape keys at the current frame), or the basis."""
    source = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()) if evaluated else obj
    mesh = source.data
    co = np.empty(len(mesh.vertices) * 3, np.float64)
    mesh.vertices.foreach_get("co", co)
    world = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3]


def key_positions(obj, name):
    """(n, 3) world positions of shape key `name` at full weight."""
    key = obj.data.shape_keys.key_blocks[name]
    co = np.empty(len(obj.data.vertices) * 3, np.float64)
    key.data.foreach_get("co", co)
    world = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3]


def skin_vertices(obj):
    """The vertices of the material with the most faces (the skin)."""
    mesh = obj.data
    materials = np.empty(len(mesh.polygons), np.int64)
    mesh.polygons.foreach_get("material_index", materials)
    skin = np.bincount(materials).argmax()
    loops = np.empty(len(mesh.loops), np.int64)
    mesh.loops.foreach_get("vertex_index", loops)
    starts = np.empty(len(mesh.polygons), np.int64)
    totals = np.empty(len(mesh.polygons), np.int64)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    used = [loops[s:s + t] for s, t, m in zip(starts, totals, materials) if m == skin]
    return np.unique(np.concatenate(used))


def lip_pair(obj):
    """The inner-lip contact on the midline (as hosts/python/tests/conftest.py finds it): of the
    skin's midline vertices, the nearest pair at rest of one jawOpen carries and one it leaves."""
    rest = key_positions(obj, obj.data.shape_keys.reference_key.name)
    moved = np.linalg.norm(key_positions(obj, "jawOpen") - rest, axis=1)
    skin = skin_vertices(obj)
    size = np.ptp(rest[skin], axis=0).max()
    midline = skin[np.abs(rest[skin, 0] - np.median(rest[skin, 0])) <= 0.01 * size]
    lower = midline[moved[midline] >= 0.5 * moved.max()]
    upper = midline[moved[midline] <= 0.1 * moved.max()]
    distances = np.linalg.norm(rest[lower][:, None, :] - rest[upper][None, :, :], axis=2)
    i, j = np.unravel_index(np.argmin(distances), distances.shape)
    return upper[j], lower[i]


def apertures(obj, frames):
    """The lip aperture at each frame, on the mesh Blender evaluates (the baked keys driving it)."""
    upper, lower = lip_pair(obj)
    result = []
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        positions = world_positions(obj)
        result.append(np.linalg.norm(positions[upper] - positions[lower]))
    return np.array(result)


def bake_range(obj):
    """(first, last) keyframe over the F-curves of the shape keys facerig's last bake animates."""
    names = set(obj["facerig"]["bake"]["names"])
    action = obj.data.shape_keys.animation_data.action
    frames = [p.co.x for fc in action.fcurves for p in fc.keyframe_points
              if fc.data_path.split('"')[1] in names]
    return min(frames), max(frames)


def check_bilabials_close(obj, phonemes, first_frame, fps):
    """Every p/b/m of the line: the lips closed (aperture under a tenth of the widest) at some frame
    from 60 ms before it starts to its end. Evaluated at those frames and every other frame of the
    bake (for the widest). Returns how many were checked."""
    first, last = bake_range(obj)
    assert first == first_frame, f"the bake starts at frame {first}, not {first_frame}"
    windows = [(p, (first_frame + (p.start - 0.06) * fps, first_frame + (p.start + max(p.duration, 0.03)) * fps))
               for p in phonemes if p.symbol in BILABIALS]
    frames = set(range(int(first), int(last) + 1, 2))
    for _, (low, high) in windows:
        frames |= set(range(int(np.ceil(low)), int(np.floor(high)) + 1))
    frames = np.array(sorted(frames))
    aperture = apertures(obj, frames)
    widest = aperture.max()
    assert widest > 0.02 * np.ptp(world_positions(obj, evaluated=False), axis=0).max(), "the mouth never opens"
    for p, (low, high) in windows:
        during = (frames >= low) & (frames <= high)
        assert during.any(), f"no frame near {p.symbol} at {p.start:.3f} s"
        closed = aperture[during].min()
        assert closed < 0.1 * widest, f"{p.symbol} at {p.start:.3f} s: aperture {closed:.4f} of {widest:.4f}"
    log(f"{len(windows)} p/b/m closed (aperture under 10% of the widest, {widest:.4f}) at "
        f"{fps:g} fps; {len(frames)} frames evaluated")
    return len(windows)


def sound_strip(name):
    return bpy.context.scene.sequence_editor.sequences_all[name]


def material_triangles(obj, material):
    """(t, 3) vertex indices of the triangles of obj's material named `material`."""
    mesh = obj.data
    index = [slot.material.name if slot.material else "" for slot in obj.material_slots].index(material)
    mesh.calc_loop_triangles()
    triangles = np.empty(len(mesh.loop_triangles) * 3, np.int64)
    materials = np.empty(len(mesh.loop_triangles), np.int64)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    mesh.loop_triangles.foreach_get("material_index", materials)
    return triangles.reshape(-1, 3)[materials == index]


def covered_fraction(points, triangles, positions):
    """The fraction of `points` ((p, 3), world) that the triangles (world `positions`) hide from the
    front (a camera looking along +Y): a triangle around the point in X-Z, nearer in Y."""
    corners = positions[triangles]
    middle = points.mean(axis=0)
    corners = corners[np.linalg.norm(corners.mean(axis=1) - middle, axis=1) < 3 * np.ptp(points, axis=0).max()]
    a, b, c = corners[:, 0][:, [0, 2]], corners[:, 1][:, [0, 2]], corners[:, 2][:, [0, 2]]
    depth = corners[:, :, 1].mean(axis=1)
    v0, v1 = b - a, c - a
    denominator = v0[:, 0] * v1[:, 1] - v1[:, 0] * v0[:, 1]
    denominator[denominator == 0] = np.inf
    hidden = 0
    for point in points:
        v2 = point[[0, 2]] - a
        s = (v2[:, 0] * v1[:, 1] - v1[:, 0] * v2[:, 1]) / denominator
        t = (v0[:, 0] * v2[:, 1] - v2[:, 0] * v0[:, 1]) / denominator
        hidden += np.any((s >= 0) & (t >= 0) & (s + t <= 1) & (depth < point[1]))
    return hidden / len(points)


class _Recorder:
    """A stand-in for Blender's UILayout: records what a panel draws, and checks every property it
    shows or sets exists (on the settings, or on the operator a button runs)."""

    def __init__(self, drawn):
        self.drawn = drawn

    def box(self):
        return self

    def row(self):
        return self

    def label(self, text="", icon="NONE"):
        self.drawn.append(("label", text))

    def prop(self, data, name, text=None):
        assert name in data.bl_rna.properties, name
        self.drawn.append(("prop", name))

    def operator(self, idname, text=None):
        category, name = idname.split(".")
        properties = getattr(getattr(bpy.ops, category), name).get_rna_type().properties
        drawn = self.drawn
        drawn.append(("operator", idname))

        class Button:
            def __setattr__(self, key, value):
                assert key in properties, f"{idname} has no property {key}"
                drawn.append(("set", idname, key, value))
        return Button()


def draw_panel():
    """What the add-on's sidebar panel draws in the current context."""
    drawn = []
    panel = bpy.types.FACERIG_PT_panel
    fake = type("Panel", (), {"layout": _Recorder(drawn)})()
    panel.draw(fake, bpy.context)
    return drawn
