"""facerig for Blender: ARKit and viseme shape keys built on your own mesh, speech baked to keyframes.

Calls facerig through its Python package (ctypes over the C ABI: libfacerig,
libfacerig_espeak, libfacerig_offline), in Blender's process. See
docs/blender.md.
"""
bl_info = {
    "name": "facerig",
    "author": "facerig",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > facerig",
    "description": "ARKit and viseme shape keys on your mesh, lip-sync from text or audio baked to keyframes, "
                   "talking heads from a photo",
    "doc_url": "https://github.com/facerig/facerig/blob/main/docs/blender.md",
    "category": "Animation",
}

import bpy

from . import build, clear, panel, photo, speak


class FacerigPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    ict_folder: bpy.props.StringProperty(
        name="ICT-FaceKit Folder", subtype="DIR_PATH",
        description="The ICT-FaceKit folder (its OBJs), the default template of Build Face Shapes")
    library_dir: bpy.props.StringProperty(
        name="Library Folder", subtype="DIR_PATH",
        description="A facerig build's build/lib (libfacerig*.so.0), for development; empty: the libraries "
                    "bundled with the add-on. Takes effect after restarting Blender")

    def draw(self, context):
        self.layout.prop(self, "ict_folder")
        self.layout.prop(self, "library_dir")


_CLASSES = (FacerigPreferences, build.FACERIG_OT_build_shapes, speak.FACERIG_OT_speak, photo.FACERIG_OT_head_from_photo,
            clear.FACERIG_OT_clear, *panel.CLASSES)


def register():
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    panel.register()


def unregister():
    panel.unregister()
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
