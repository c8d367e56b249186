"""Build face shapes: the ARKit and viseme shapes of a template, built on the selected mesh's own
vertices (facerig.offline.build) and written onto it as shape keys."""
import os
import shutil
import tempfile

import bpy
import numpy as np
from mathutils import Vector

from . import library, mesh_export, shape_keys, templates
from .jobs import Job, JobOperator, UserError

# The built rig's neutral must be the exported positions: anything further off
# means its vertices are not the mesh's (a fraction of the bounding diagonal).
MATCH_TOLERANCE = 1e-5


def selected_meshes(context):
    """The active mesh first, then the other selected meshes (its eyes, teeth, lashes)."""
    active = context.active_object
    if active is None or active.type != "MESH":
        raise UserError("select the face mesh (make it the active object)")
    others = [obj for obj in context.selected_objects if obj.type == "MESH" and obj != active]
    for obj in [active] + others:
        if obj.mode == "EDIT":
            raise UserError(f"'{obj.name}' is in Edit Mode: go back to Object Mode first")
        if len(obj.data.polygons) == 0:
            raise UserError(f"'{obj.name}' has no faces")
    return [active] + sorted(others, key=lambda obj: obj.name)


def _world_bounds(obj):
    corners = np.array([obj.matrix_world @ Vector(corner) for corner in obj.bound_box])
    return corners.min(axis=0), corners.max(axis=0)


def left_out(context, objects):
    """Meshes not selected whose middle lies inside the face's bounds (eyes, teeth, lashes left
    out of the build)."""
    low, high = _world_bounds(objects[0])
    found = []
    for obj in context.view_layer.objects:
        if obj.type != "MESH" or obj in objects or not obj.visible_get():
            continue
        obj_low, obj_high = _world_bounds(obj)
        middle = (obj_low + obj_high) / 2
        if np.all(middle >= low) and np.all(middle <= high):
            found.append(obj.name)
    return sorted(found)


def shape_deltas(rig, rows, written, progress):
    """Each shape's (rows, 3) deltas on the rig's first `rows` vertices, from one-hot blends."""
    facerig = library.facerig()
    neutral, _ = rig.neutral()
    if rig.vertex_count < rows:
        raise UserError(f"the built rig has {rig.vertex_count} vertices, fewer than the {rows} exported")
    drift = float(np.abs(neutral[:rows] - written).max())
    if drift > MATCH_TOLERANCE * rig.bounding_diagonal:
        raise facerig.FacerigError(f"the built rig's vertices are not the mesh's (off by {drift:g}); "
                                   "please report this")
    weights = np.zeros(rig.shape_count, np.float32)
    blended = np.empty((rig.vertex_count, 3), np.float32)
    deltas = np.empty((rig.shape_count, rows, 3), np.float32)
    for i in range(rig.shape_count):
        progress("read shapes", i, rig.shape_count)
        weights[:] = 0.0
        weights[i] = 1.0
        rig.blend(weights, out=blended)
        deltas[i] = blended[:rows] - neutral[:rows]
    return deltas


class FACERIG_OT_build_shapes(JobOperator, bpy.types.Operator):
    """Build the 52 ARKit and 15 viseme shapes on the active mesh (and the selected eyes, teeth,
    lashes) as shape keys, from an ICT-FaceKit template or the built-in head"""
    bl_idname = "facerig.build_shapes"
    bl_label = "Build Face Shapes"
    bl_options = {"REGISTER", "UNDO"}

    template: bpy.props.EnumProperty(
        name="Template", items=templates.TEMPLATE_ITEMS, default="ICT",
        description="The rig whose expressions are built on the mesh")
    template_folder: bpy.props.StringProperty(
        name="ICT-FaceKit Folder", subtype="DIR_PATH",
        description="The ICT-FaceKit folder (empty: the add-on's preference)")

    @classmethod
    def poll(cls, context):
        return context.mode == "OBJECT"

    def prepare(self, context):
        return build_job(context, self.template, self.template_folder)


def build_job(context, template_kind, template_folder=""):
    """The Job that builds the selected meshes' shapes (the operator's work, also for tests)."""
    objects = selected_meshes(context)
    template = templates.resolve(template_kind, template_folder)
    offline, facerig = library.module("offline"), library.facerig()
    work_dir = tempfile.mkdtemp(prefix="facerig-build-")
    try:
        target = os.path.join(work_dir, "target.obj")
        exported, written = mesh_export.write_obj(target, objects)
        missing = left_out(context, objects)
    except BaseException:
        shutil.rmtree(work_dir, ignore_errors=True)
        raise

    def work(progress):
        template_path = template.path(progress)
        try:
            offline.build(template=template_path, target=target, output=os.path.join(work_dir, "rig.frig"),
                          progress=progress, **template.options)
        except facerig.FailedError as error:
            if "no face" not in str(error):
                raise
            raise UserError(f"{error}. In Blender: the face looks toward -Y (the Front view), Z up") from None
        with facerig.Rig(os.path.join(work_dir, "rig.frig")) as rig:
            return rig.shape_names, shape_deltas(rig, len(written), written, progress)

    def apply(result):
        names, deltas = result
        return apply_shapes(objects, exported, names, deltas, template, missing)

    return Job("Building face shapes", work, apply, lambda: shutil.rmtree(work_dir, ignore_errors=True))


def apply_shapes(objects, exported, names, deltas, template, missing):
    """Writes the built shapes onto the objects; the message to report."""
    for obj, item in zip(objects, exported):
        if obj.name != item.name or len(obj.data.vertices) != item.vertex_count:
            raise UserError(f"'{item.name}' changed while facerig was building: build again")
        shape_keys.check_names_free(obj, names)
    face, parts = objects[0], objects[1:]
    shape_keys.write_shapes(face, names, mesh_export.local_deltas(exported[0], deltas))
    moved = []
    for obj, item in zip(parts, exported[1:]):
        written = shape_keys.write_shapes(obj, names, mesh_export.local_deltas(item, deltas), moving_only=True)
        moved.append(f"{obj.name} ({len(written)})")
    values = shape_keys.record(face)
    values["parts"] = [obj.name for obj in parts]
    values["template"] = template.label
    values["left_out"] = missing
    shape_keys.save_record(face, values)
    message = f"facerig: {len(names)} shape keys on '{face.name}' from {template.label}"
    if moved:
        message += "; on " + ", ".join(moved)
    if missing:
        message += (f". Not selected, so without shapes: {', '.join(missing)} "
                    "(select them with the face to build theirs too)")
    return message
