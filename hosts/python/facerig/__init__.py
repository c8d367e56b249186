"""facerig for Python: talking faces through facerig's C ABI (libfacerig, ctypes).

    import facerig
    rig = facerig.Rig("default_head.frig")
    character = facerig.Character(rig)
    character.speak(facerig.Speech.from_track("line.json"))
    weights = character.update(0.5)          # float32, one per shape
    positions = rig.blend(weights)           # (vertex_count, 3) float32

Text-to-speech (espeak-ng, GPL-3) is in facerig.tts; the offline tools (rig
building, photo heads, the built-in head, conversion) in facerig.offline.
"""
from ._native import library_path
from .audio import AudioStream
from .character import EMOTIONS, VISEMES, Character
from .errors import (BufferTooSmallError, CancelledError, ClosedError, FacerigError, FailedError, FileError,
                     FormatError, InvalidArgumentError, LimitError, NotFoundError, SpeechError, StateError)
from .rig import Rig
from .speech import Phoneme, Speech

__all__ = ["AudioStream", "BufferTooSmallError", "CancelledError", "Character", "ClosedError", "FailedError", "EMOTIONS", "FacerigError",
           "FileError", "FormatError", "InvalidArgumentError", "LimitError", "NotFoundError", "Phoneme", "Rig",
           "Speech", "SpeechError", "StateError", "VISEMES", "library_path"]
