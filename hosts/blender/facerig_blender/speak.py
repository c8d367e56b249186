"""Speak: a line (typed text and a voice, a recording and its transcript, or a recording alone)
baked to the selected face's shape-key keyframes at the scene's frame rate, with blinks, idle gaze
and an optional emotion, and its audio as a sound strip at the first baked frame."""
import math
import os
import re
import uuid
import wave

import bpy
import numpy as np

from . import bake, library, names, shape_keys
from .build import selected_meshes
from .jobs import Job, JobOperator, UserError
from .mesh_export import basis_positions

SOURCE_ITEMS = [
    ("TEXT", "Text", "Typed text, spoken by espeak-ng in the chosen voice"),
    ("RECORDING", "Recording + Transcript", "A recording and what it says, aligned (any espeak-ng language)"),
    ("AUDIO", "Recording Only", "A recording without its transcript: the rough mode, a coarse mouth"),
]
EMOTION_ITEMS = [("NONE", "None", "")] + [(e.upper(), e.capitalize(), "") for e in
                                          ("joy", "sadness", "fear", "anger", "surprise", "disgust")]
TAIL_SECONDS = 0.4  # baked after the line, for the mouth to come to rest


def spoken_shapes(obj):
    """The shape keys Speak animates on obj: those facerig wrote, else its ARKit and viseme keys."""
    keys = obj.data.shape_keys
    present = set(keys.key_blocks.keys()) if keys else set()
    owned = [name for name in shape_keys.owned_shapes(obj) if name in present]
    if owned:
        return owned
    return [key.name for key in keys.key_blocks if key.name in names.SPOKEN] if keys else []


def rig_from_shape_keys(obj, shapes):
    """A facerig rig of obj's mesh and its shape keys `shapes` (what a Character speaks with)."""
    facerig = library.facerig()
    mesh = obj.data
    mesh.calc_loop_triangles()
    triangles = np.empty(len(mesh.loop_triangles) * 3, np.uint32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    basis = basis_positions(mesh)
    deltas = np.empty((len(shapes), len(basis), 3), np.float32)
    co = np.empty(basis.size, np.float32)
    for i, name in enumerate(shapes):
        mesh.shape_keys.key_blocks[name].data.foreach_get("co", co)
        deltas[i] = co.reshape(-1, 3) - basis
    return facerig.Rig.from_arrays(basis, triangles, shapes, deltas)


def write_wav(path, samples, rate):
    """16-bit mono WAV for the sound strip (packed into the .blend afterwards)."""
    pcm = (np.clip(samples, -1.0, 1.0) * 32767.0).astype("<i2")
    with wave.open(path, "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(2)
        out.setframerate(rate)
        out.writeframes(pcm.tobytes())


class FACERIG_OT_speak(JobOperator, bpy.types.Operator):
    """Bake a spoken line onto the active face's shape keys (with blinks and an optional emotion),
    its audio as a sound strip at the first baked frame; replaces the previous bake"""
    bl_idname = "facerig.speak"
    bl_label = "Speak"
    bl_options = {"REGISTER", "UNDO"}

    source: bpy.props.EnumProperty(name="Source", items=SOURCE_ITEMS, default="TEXT")
    text: bpy.props.StringProperty(name="Text", description="What the character says (Text source)")
    voice: bpy.props.StringProperty(name="Voice", default="en-us",
                                    description="An espeak-ng language: en-us, en-gb, de, fr, pt-br, ...")
    audio_path: bpy.props.StringProperty(name="Recording", subtype="FILE_PATH",
                                         description="WAV, FLAC, Ogg/Vorbis or AIFF")
    transcript: bpy.props.StringProperty(name="Transcript", description="What the recording says")
    emotion: bpy.props.EnumProperty(name="Emotion", items=EMOTION_ITEMS, default="NONE")
    emotion_strength: bpy.props.FloatProperty(name="Strength", default=0.6, min=0.0, max=1.0)
    blinks: bpy.props.BoolProperty(name="Blinks", default=True)
    gaze: bpy.props.BoolProperty(name="Eye Movements", default=True, description="Idle saccades")
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0, description="Blinks and gaze: same seed, same motion")
    use_current_frame: bpy.props.BoolProperty(name="At Current Frame", default=True)
    start_frame: bpy.props.IntProperty(name="Start Frame", default=1)

    @classmethod
    def poll(cls, context):
        return context.mode == "OBJECT"

    def _line(self, facerig):
        """work(progress) -> Speech for the chosen source (its checks here, on the main thread)."""
        voice = self.voice.strip() or "en-us"
        if self.source == "TEXT":
            if not self.text.strip():
                raise UserError("type the text to speak")
            tts, text = library.module("tts"), self.text
            return lambda: tts.synthesize(text, voice)
        path = library.bpy_path(self.audio_path)
        if not path:
            raise UserError("choose the recording to speak")
        if self.source == "RECORDING":
            if not self.transcript.strip():
                raise UserError("type the recording's transcript (or choose Recording Only)")
            tts, transcript = library.module("tts"), self.transcript

            def aligned():
                samples, rate = facerig.Speech.from_audio_file(path).audio
                return tts.align(samples, rate, transcript, voice)
            return aligned
        return lambda: facerig.Speech.from_audio(*facerig.Speech.from_audio_file(path).audio)

    def prepare(self, context):
        facerig = library.facerig()
        face = selected_meshes(context)[0]
        shapes = spoken_shapes(face)
        if not shapes:
            raise UserError(f"'{face.name}' has no ARKit or viseme shape keys: run Build Face Shapes first")
        line = self._line(facerig)
        rig = rig_from_shape_keys(face, shapes)
        scene = context.scene
        fps = scene.render.fps / scene.render.fps_base
        first = scene.frame_current if self.use_current_frame else self.start_frame
        options = dict(seed=self.seed, blinks=self.blinks, gaze=self.gaze)
        emotion = None if self.emotion == "NONE" else (self.emotion.lower(), self.emotion_strength)
        wav = None
        if self.source == "TEXT":
            stem = re.sub(r"[^A-Za-z0-9_-]+", "_", face.name)
            wav = os.path.join(bpy.app.tempdir, f"facerig_{stem}_{uuid.uuid4().hex[:8]}.wav")
        audio = wav or library.bpy_path(self.audio_path)

        def work(progress):
            progress("speech", 0, 0)
            speech = line()
            samples, rate = speech.audio
            phonemes = speech.phonemes
            if not phonemes:
                raise UserError("the line has no phonemes (nothing to say)")
            end = max(samples.size / rate if rate else 0.0, phonemes[-1].start + phonemes[-1].duration)
            frames = math.ceil((end + TAIL_SECONDS) * fps) + 1
            progress("animate", 0, frames)
            with facerig.Character(rig, **options) as character:
                if emotion:
                    character.set_emotion(*emotion)
                    character.update(-2.0)  # the emotion is up by the first frame
                character.speak(speech, 0.0)
                weights = np.empty((frames, rig.shape_count), np.float32)
                for k in range(frames):
                    character.update(k / fps, out=weights[k])
            if wav:
                write_wav(wav, samples, rate)
            return weights, phonemes

        def apply(result):
            weights, phonemes = result
            return self.apply_bake(scene, face, shapes, first, weights, audio, wav is not None)

        return Job("Speaking", work, apply, rig.close)

    def apply_bake(self, scene, face, shapes, first, weights, audio, packed):
        values = shape_keys.record(face)
        previous = values.get("bake")
        bake.clear_bake(face)
        last = first + weights.shape[0] - 1
        targets = [face] + [bpy.data.objects[name] for name in values.get("parts", []) if name in bpy.data.objects]
        added = []
        for target in targets:
            if target.data.shape_keys is None:
                continue
            bake.remove_keys(target, shapes, [(first, last)])
            if bake.write_keys(target, shapes, first, weights):
                added.append(target.name)
        strip = bake.add_sound(scene, f"{face.name} speech", audio, first, last, packed)
        values = shape_keys.record(face)
        values["bake"] = {"first": first, "last": last, "names": shapes, "scene": scene.name,
                          "strip": strip.name, "actions_added": added}
        shape_keys.save_record(face, values)
        replaced = " (replacing the previous bake)" if previous else ""
        return (f"facerig: baked frames {first}-{last} on {len(shapes)} shape keys of "
                f"{', '.join(t.name for t in targets)}, sound strip '{strip.name}' at frame {first}{replaced}")
