"""Speech baked into the scene: shape-key keyframes, one per frame, and the line's audio as a sound
strip at the bake's first frame; and taking a bake out again.

A bake owns its frame range on the shape keys it animates: re-baking removes
the previous bake's keys (its range, recorded on the object under
facerig["bake"]) and any key in the new range on those shape keys, then adds
its own; keys elsewhere, other shape keys and other strips stay.
"""
import numpy as np

from . import shape_keys

LINEAR = 1  # the 'LINEAR' item of FCurve keyframe interpolation, for foreach_set


def data_path(name):
    return f'key_blocks["{name}"].value'


def _remove_keys(fcurve, first, last):
    """Removes fcurve's keyframes in [first, last]; True when it is left empty."""
    points = fcurve.keyframe_points
    frames = np.empty(len(points) * 2, np.float32)
    points.foreach_get("co", frames)
    frames = frames[0::2]
    inside = np.flatnonzero((frames >= first - 0.5) & (frames <= last + 0.5))
    if len(inside) == len(points):
        points.clear()
    else:
        for index in inside[::-1]:
            points.remove(points[int(index)], fast=True)
        fcurve.update()
    return len(points) == 0


def remove_keys(obj, names, ranges, drop_empty_action=False):
    """Removes the keyframes of obj's shape keys `names` within each (first, last) of `ranges`, the
    F-curves left empty and, with drop_empty_action (the add-on made it), an action left empty."""
    key = obj.data.shape_keys
    action = key.animation_data.action if key is not None and key.animation_data else None
    if action is None:
        return
    for name in names:
        fcurve = action.fcurves.find(data_path(name))
        if fcurve is None:
            continue
        empty = False
        for first, last in ranges:
            empty = _remove_keys(fcurve, first, last)
        if empty:
            action.fcurves.remove(fcurve)
    if len(action.fcurves) == 0 and drop_empty_action:
        key.animation_data.action = None
        if action.users == 0:
            import bpy
            bpy.data.actions.remove(action)


def write_keys(obj, names, first_frame, weights):
    """Keyframes on obj's shape keys `names` (those it has): weights[k, i] at first_frame + k.
    Returns whether the add-on made the action."""
    import bpy
    key = obj.data.shape_keys
    animation = key.animation_data or key.animation_data_create()
    added = animation.action is None
    if added:
        animation.action = bpy.data.actions.new(f"{obj.name} facerig speech")
    action = animation.action
    frames = first_frame + np.arange(weights.shape[0], dtype=np.float32)
    for i, name in enumerate(names):
        if name not in key.key_blocks:
            continue
        fcurve = action.fcurves.find(data_path(name)) or action.fcurves.new(data_path(name), action_group="facerig")
        points = fcurve.keyframe_points
        start = len(points)
        points.add(len(frames))
        co = np.empty(len(points) * 2, np.float32)
        points.foreach_get("co", co)
        co[2 * start::2] = frames
        co[2 * start + 1::2] = weights[:, i]
        points.foreach_set("co", co)
        interpolation = np.empty(len(points), np.int32)
        points.foreach_get("interpolation", interpolation)
        interpolation[start:] = LINEAR
        points.foreach_set("interpolation", interpolation)
        fcurve.update()
    return added


def free_channel(sequences, first, last):
    """The lowest channel with no strip overlapping frames [first, last]."""
    taken = {strip.channel for strip in sequences
             if strip.frame_final_start <= last and strip.frame_final_end > first}
    channel = 1
    while channel in taken:
        channel += 1
    return channel


def add_sound(scene, name, path, first, last, pack):
    """A sound strip of `path` starting at frame `first`; packed into the .blend when `pack`."""
    editor = scene.sequence_editor or scene.sequence_editor_create()
    sequences = editor.sequences
    strip = sequences.new_sound(name, path, free_channel(sequences, first, last), first)
    if pack:
        strip.sound.pack()
    return strip


def remove_sound(scene, strip_name):
    import bpy
    editor = scene.sequence_editor if scene else None
    strip = editor.sequences.get(strip_name) if editor and strip_name else None
    if strip is None:
        return
    sound = strip.sound
    editor.sequences.remove(strip)
    if sound is not None and sound.users == 0:
        bpy.data.sounds.remove(sound)


def clear_bake(obj):
    """Takes the object's last bake out: its keys (on the object and the parts built with it) and
    its sound strip. Returns whether there was one."""
    import bpy
    values = shape_keys.record(obj)
    bake = values.get("bake")
    if not bake:
        return False
    span = [(bake["first"], bake["last"])]
    for name in [obj.name] + list(values.get("parts", [])):
        target = bpy.data.objects.get(name)
        if target is not None and target.type == "MESH":
            remove_keys(target, bake.get("names", []), span, name in bake.get("actions_added", []))
    remove_sound(bpy.data.scenes.get(bake.get("scene", "")), bake.get("strip", ""))
    values = shape_keys.record(obj)
    values.pop("bake", None)
    shape_keys.save_record(obj, values)
    return True
