"""Frames of a baked character rendered headless with Workbench (the docs' pictures):
speaking_frame() renders the face at a closed p/b/m and at its widest vowel, side by side."""
import os

import bpy
import numpy as np

import helpers


def _camera_on(obj, size=400):
    """An orthographic camera looking at the face from the front (along +Y), framing its skin."""
    rest = helpers.world_positions(obj, evaluated=False)[helpers.skin_vertices(obj)]
    low, high = rest.min(axis=0), rest.max(axis=0)
    middle = (low + high) / 2
    data = bpy.data.cameras.new("facerig camera")
    data.type = "ORTHO"
    data.ortho_scale = 1.05 * max(high[0] - low[0], high[2] - low[2])
    camera = bpy.data.objects.new("facerig camera", data)
    camera.location = (middle[0], low[1] - 3 * (high[1] - low[1]), middle[2])
    camera.rotation_euler = (np.pi / 2, 0.0, 0.0)
    data.clip_end = 10 * (high[1] - low[1]) + 10
    bpy.context.scene.collection.objects.link(camera)
    scene = bpy.context.scene
    scene.camera = camera
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    shading = scene.display.shading
    shading.light, shading.color_type = "STUDIO", "MATERIAL"
    shading.show_cavity = True
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    scene.view_settings.view_transform = "Standard"  # the PNGs read back and saved unchanged
    return camera


def _render(frame, path):
    bpy.context.scene.frame_set(frame)
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)
    shape = (image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels.reshape(shape)


def _see_through(obj):
    """Overlay materials (ICT-FaceKit's eye occlusion, tear film, eye blend) drawn transparent, as
    they are meant to be: Workbench would paint them opaque over the eyes."""
    for slot in obj.material_slots:
        material = slot.material
        if material and any(word in material.name for word in ("Occlusion", "Lacrimal", "EyeBlend")):
            material.diffuse_color[3] = 0.0
            material.blend_method = "BLEND"


def speaking_frame(obj, phonemes, first_frame, fps, out, color="MATERIAL"):
    """Renders `out`: obj at the frame nearest its first p/b/m (lips closed) and at its widest
    mouth with the eyes open, side by side."""
    _camera_on(obj)
    _see_through(obj)
    bpy.context.scene.display.shading.color_type = color
    first, last = helpers.bake_range(obj)
    frames = np.arange(int(first), int(last) + 1)
    aperture = helpers.apertures(obj, frames)
    blink = obj.data.shape_keys.animation_data.action.fcurves.find('key_blocks["eyeBlinkLeft"].value')
    aperture[[blink.evaluate(frame) > 0.1 for frame in frames]] = 0.0
    bilabial = next(p for p in phonemes if p.symbol in helpers.BILABIALS)
    closed = int(round(first_frame + (bilabial.start + bilabial.duration / 2) * fps))
    widest = int(frames[np.argmax(aperture)])
    panels = [_render(frame, out + f".{frame}.png") for frame in (closed, widest)]
    for frame in (closed, widest):
        os.remove(out + f".{frame}.png")
    joined = np.concatenate(panels, axis=1)
    image = bpy.data.images.new("facerig frames", joined.shape[1], joined.shape[0], alpha=True)
    image.pixels.foreach_set(joined.ravel())
    image.save_render(out, scene=bpy.context.scene)  # the scene's PNG settings: RGB, most compressed
    bpy.data.images.remove(image)
    helpers.log(f"frames {closed} ('{bilabial.symbol}', lips closed) and {widest} (widest) in {out}")
