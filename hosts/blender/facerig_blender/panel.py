"""The facerig tab of the 3D Viewport's sidebar: the operators with their settings (kept per scene)."""
import bpy

from . import library, shape_keys, speak, templates

_voice_items = []  # Blender needs the items of a dynamic enum kept alive


def voice_items(self, context):
    if not _voice_items:
        try:
            voices = library.module("tts").voices()
        except Exception:  # no espeak-ng: the field still shows the default
            voices = ["en-us"]
        voices = sorted(voices, key=lambda voice: voice != "en-us")  # the first is the default
        _voice_items.extend((v, v, "") for v in voices)
    return _voice_items


class FacerigSettings(bpy.types.PropertyGroup):
    template: bpy.props.EnumProperty(name="Template", items=templates.TEMPLATE_ITEMS, default="ICT")
    template_folder: bpy.props.StringProperty(name="ICT-FaceKit Folder", subtype="DIR_PATH")
    source: bpy.props.EnumProperty(name="Source", items=speak.SOURCE_ITEMS, default="TEXT")
    text: bpy.props.StringProperty(name="Text", default="Peter picked a peck of pickled peppers.")
    voice: bpy.props.EnumProperty(name="Voice", items=voice_items)
    audio_path: bpy.props.StringProperty(name="Recording", subtype="FILE_PATH")
    transcript: bpy.props.StringProperty(name="Transcript")
    emotion: bpy.props.EnumProperty(name="Emotion", items=speak.EMOTION_ITEMS, default="NONE")
    emotion_strength: bpy.props.FloatProperty(name="Strength", default=0.6, min=0.0, max=1.0)
    blinks: bpy.props.BoolProperty(name="Blinks", default=True)
    gaze: bpy.props.BoolProperty(name="Eye Movements", default=True)
    photo: bpy.props.StringProperty(name="Photo", subtype="FILE_PATH")


class FACERIG_PT_panel(bpy.types.Panel):
    bl_label = "facerig"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "facerig"

    def draw(self, context):
        settings = context.scene.facerig
        layout = self.layout
        face = context.active_object

        box = layout.box()
        box.label(text="Face Shapes", icon="SHAPEKEY_DATA")
        box.prop(settings, "template")
        if settings.template == "ICT":
            box.prop(settings, "template_folder", text="Folder")
        op = box.operator("facerig.build_shapes")
        op.template, op.template_folder = settings.template, settings.template_folder

        box = layout.box()
        box.label(text="Speak", icon="SPEAKER")
        box.prop(settings, "source")
        if settings.source == "TEXT":
            box.prop(settings, "text")
        else:
            box.prop(settings, "audio_path")
            if settings.source == "RECORDING":
                box.prop(settings, "transcript")
        if settings.source != "AUDIO":
            box.prop(settings, "voice")
        row = box.row()
        row.prop(settings, "emotion")
        if settings.emotion != "NONE":
            row.prop(settings, "emotion_strength")
        row = box.row()
        row.prop(settings, "blinks")
        row.prop(settings, "gaze")
        op = box.operator("facerig.speak")
        for name in ("source", "text", "audio_path", "transcript", "emotion", "emotion_strength", "blinks", "gaze"):
            setattr(op, name, getattr(settings, name))
        op.voice = settings.voice or "en-us"

        box = layout.box()
        box.label(text="Head from Photo", icon="IMAGE_DATA")
        box.prop(settings, "photo", text="")
        box.operator("facerig.head_from_photo").filepath = settings.photo

        if face is not None and shape_keys.record(face):
            row = layout.row()
            row.operator("facerig.clear", text="Clear Bake").what = "BAKE"
            row.operator("facerig.clear", text="Clear All").what = "ALL"


CLASSES = (FacerigSettings, FACERIG_PT_panel)


def register():
    bpy.types.Scene.facerig = bpy.props.PointerProperty(type=FacerigSettings)


def unregister():
    del bpy.types.Scene.facerig
