"""Clear: takes out what the add-on added to the active object (its last bake, and with it the
shape keys it built)."""
import bpy

from . import bake, shape_keys

WHAT_ITEMS = [
    ("BAKE", "Bake", "The last Speak bake: its keyframes and sound strip"),
    ("ALL", "Everything", "The bake, and the shape keys facerig added (also on the parts built with it)"),
]


class FACERIG_OT_clear(bpy.types.Operator):
    """Remove what facerig added to the active object: its speech bake, or also its shape keys"""
    bl_idname = "facerig.clear"
    bl_label = "Clear facerig"
    bl_options = {"REGISTER", "UNDO"}

    what: bpy.props.EnumProperty(name="What", items=WHAT_ITEMS, default="ALL")

    @classmethod
    def poll(cls, context):
        return context.mode == "OBJECT" and context.active_object is not None

    def execute(self, context):
        face = context.active_object
        values = shape_keys.record(face)
        if not values:
            self.report({"ERROR"}, f"facerig added nothing to '{face.name}'")
            return {"CANCELLED"}
        removed = ["the bake"] if bake.clear_bake(face) else []
        if self.what == "ALL":
            parts = [bpy.data.objects[name] for name in values.get("parts", []) if name in bpy.data.objects]
            for obj in [face] + parts:
                if shape_keys.owned_shapes(obj):
                    removed.append(f"the shape keys of '{obj.name}'")
                shape_keys.remove_shapes(obj)
        self.report({"INFO"}, "facerig: removed " + (", ".join(removed) if removed else "nothing"))
        return {"FINISHED"}

