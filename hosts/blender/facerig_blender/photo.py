"""Head from Photo: a new textured object with facerig's shape keys, from one photograph
(facerig.offline.photo), brought in through Blender's glTF importer (the C ABI gives the mesh and
its shapes, not its materials and textures; the GLB carries all of them)."""
import os
import shutil
import tempfile

import bpy
import numpy as np

from . import library, shape_keys
from .jobs import Job, JobOperator, UserError


def import_gltf(path):
    """Blender's glTF importer on `path`. Debian's Blender 3.4 importer still uses numpy.bool, which
    Debian 12's numpy 1.24 no longer has (numpy 2 has it again): the alias is lent for the call."""
    lend = "bool" not in dir(np)
    if lend:
        np.bool = bool
    try:
        bpy.ops.import_scene.gltf(filepath=path)
    finally:
        if lend:
            del np.bool


class FACERIG_OT_head_from_photo(JobOperator, bpy.types.Operator):
    """Make a new talking head, textured from a photograph of a face, with ARKit and viseme shape keys"""
    bl_idname = "facerig.head_from_photo"
    bl_label = "Head from Photo"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(name="Photo", subtype="FILE_PATH",
                                       description="A photograph of one face, looking roughly at the camera")

    @classmethod
    def poll(cls, context):
        return context.mode == "OBJECT"

    def prepare(self, context):
        return photo_job(self.filepath)


def photo_job(filepath):
    """The Job that makes a head from the photo at `filepath` (the operator's work, also for tests)."""
    image = library.bpy_path(filepath)
    if not image:
        raise UserError("choose the photo")
    if not os.path.isfile(image):
        raise UserError(f"the photo {image} does not exist")
    offline = library.module("offline")
    work_dir = tempfile.mkdtemp(prefix="facerig-photo-")
    glb = os.path.join(work_dir, "head.glb")
    name = os.path.splitext(os.path.basename(image))[0] + " head"

    def work(progress):
        return offline.photo(image, output=glb, progress=progress)

    def apply(report):
        return import_head(glb, name, image)

    return Job("Head from photo", work, apply, lambda: shutil.rmtree(work_dir, ignore_errors=True))


def import_head(glb, name, image):
    """The photo head's GLB brought in as a new object named `name`, recorded as facerig's."""
    before = set(bpy.data.objects)
    try:
        import_gltf(glb)
    except BaseException:
        for obj in set(bpy.data.objects) - before:  # no half-imported head
            bpy.data.objects.remove(obj)
        raise
    meshes = [obj for obj in bpy.data.objects if obj not in before and obj.type == "MESH"]
    if not meshes:
        raise UserError("the photo head could not be imported (Blender's glTF importer made no mesh)")
    for image_data in bpy.data.images:  # keep the texture in the .blend: the GLB is temporary
        if image_data.packed_file is None and image_data.filepath.startswith(os.path.dirname(glb)):
            image_data.pack()
    head = max(meshes, key=lambda obj: len(obj.data.vertices))
    head.name = name
    keys = head.data.shape_keys
    shapes = [key.name for key in keys.key_blocks[1:]] if keys else []
    shape_keys.save_record(head, {"shapes": shapes, "photo": image})
    bpy.context.view_layer.objects.active = head
    return f"facerig: '{head.name}' from {os.path.basename(image)}, {len(shapes)} shape keys"
