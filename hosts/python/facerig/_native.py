"""The C ABI (facerig.h, facerig_tts.h) declared for ctypes.

libfacerig is found, in this order: the file named by $FACERIG_LIBRARY; in
the folder $FACERIG_LIBRARY_DIR; next to this package (a copy installed
with it); the system's library path (libfacerig.so.0, e.g. from
`cmake --install`). libfacerig_espeak (text-to-speech, GPL-3) is looked for
beside it, then on the system's path, only when facerig.tts is used;
libfacerig_offline (the offline tools) likewise for facerig.offline.
"""
import ctypes
import os
import types
from ctypes import POINTER, Structure, c_char, c_char_p, c_double, c_float, c_int32, c_size_t, c_uint32, c_uint64, c_void_p

from .errors import ClosedError

ABI_VERSION_MAJOR = 0
ABI_VERSION_MINOR = 3
NAME_CAPACITY = 16

status = c_int32  # fr_status


class RigInfo(Structure):
    _fields_ = [("vertex_count", c_uint32), ("triangle_count", c_uint32), ("shape_count", c_uint32),
                ("part_count", c_uint32), ("has_uvs", c_uint32), ("has_normal_deltas", c_uint32),
                ("units", c_uint32), ("up_axis", c_uint32), ("bounding_diagonal", c_float)]


class PartInfo(Structure):
    _fields_ = [("first_triangle", c_uint32), ("triangle_count", c_uint32), ("first_vertex", c_uint32),
                ("vertex_count", c_uint32), ("material", c_int32)]


class Phoneme(Structure):
    _fields_ = [("start", c_double), ("duration", c_double), ("symbol", c_char * NAME_CAPACITY),
                ("language", c_char * NAME_CAPACITY), ("word_start", c_int32), ("reserved", c_int32)]


class AlignmentFit(Structure):
    _fields_ = [("confidence", c_double), ("tempo", c_double), ("fits", c_int32), ("reserved", c_int32)]


class CharacterOptions(Structure):
    _fields_ = [("seed", c_uint64), ("jaw_intensity", c_float), ("lip_intensity", c_float),
                ("key_capacity", c_uint32), ("blinks", c_uint32), ("gaze", c_uint32)]


class CharacterState(Structure):
    _fields_ = [("talking", c_int32), ("at_pause", c_int32), ("viseme", c_int32), ("blink_left", c_float),
                ("blink_right", c_float), ("gaze_x", c_float), ("gaze_y", c_float),
                ("phoneme", c_char * NAME_CAPACITY)]


P = POINTER
handle = c_void_p
float_p = P(c_float)

# name: (restype, argtypes)
_FUNCTIONS = {
    "fr_abi_version": (c_uint32, []),
    "fr_last_error": (c_char_p, []),
    "fr_status_name": (c_char_p, [status]),
    "fr_rig_load_file": (status, [c_char_p, P(handle)]),
    "fr_rig_load_bytes": (status, [c_void_p, c_size_t, c_char_p, P(handle)]),
    "fr_rig_create": (status, [float_p, c_size_t, P(c_uint32), c_size_t, P(c_char_p), float_p, c_size_t,
                               P(handle)]),
    "fr_rig_release": (None, [handle]),
    "fr_rig_get_info": (status, [handle, P(RigInfo)]),
    "fr_rig_shape_name": (status, [handle, c_uint32, c_char_p, c_size_t, P(c_size_t)]),
    "fr_rig_find_shape": (status, [handle, c_char_p, P(c_uint32)]),
    "fr_rig_part_info": (status, [handle, c_uint32, P(PartInfo)]),
    "fr_rig_part_name": (status, [handle, c_uint32, c_char_p, c_size_t, P(c_size_t)]),
    "fr_rig_neutral": (status, [handle, float_p, float_p, c_size_t, P(c_size_t)]),
    "fr_rig_uvs": (status, [handle, float_p, c_size_t, P(c_size_t)]),
    "fr_rig_triangles": (status, [handle, P(c_uint32), c_size_t, P(c_size_t)]),
    "fr_rig_blend": (status, [handle, float_p, c_size_t, c_int32, float_p, float_p, c_size_t]),
    "fr_speech_load_track_file": (status, [c_char_p, P(handle)]),
    "fr_speech_load_track_bytes": (status, [c_char_p, c_size_t, P(handle)]),
    "fr_speech_create": (status, [P(Phoneme), c_size_t, float_p, c_size_t, c_int32, P(handle)]),
    "fr_speech_from_audio": (status, [float_p, c_size_t, c_int32, P(handle)]),
    "fr_speech_load_audio_file": (status, [c_char_p, P(handle)]),
    "fr_speech_align": (status, [handle, float_p, c_size_t, c_int32, P(AlignmentFit), P(handle)]),
    "fr_speech_release": (None, [handle]),
    "fr_speech_phonemes": (status, [handle, P(Phoneme), c_size_t, P(c_size_t)]),
    "fr_speech_audio": (status, [handle, float_p, c_size_t, P(c_size_t), P(c_int32)]),
    "fr_character_default_options": (status, [P(CharacterOptions)]),
    "fr_character_create": (status, [handle, P(CharacterOptions), P(handle)]),
    "fr_character_release": (None, [handle]),
    "fr_character_speak": (status, [handle, handle, c_double]),
    "fr_character_begin_line": (status, [handle, c_double]),
    "fr_character_push_phoneme": (status, [handle, P(Phoneme)]),
    "fr_character_end_line": (status, [handle]),
    "fr_character_stop": (status, [handle]),
    "fr_character_set_emotion": (status, [handle, c_int32, c_float]),
    "fr_character_set_behaviour": (status, [handle, c_int32, c_int32]),
    "fr_character_update": (status, [handle, c_double, float_p, c_size_t]),
    "fr_character_get_state": (status, [handle, P(CharacterState)]),
    "fr_audio_stream_create_rough": (status, [c_int32, P(handle)]),
    "fr_audio_stream_create_aligned": (status, [handle, P(handle)]),
    "fr_audio_stream_push": (status, [handle, float_p, c_size_t]),
    "fr_audio_stream_finish": (status, [handle]),
    "fr_audio_stream_read": (status, [handle, P(Phoneme), c_size_t, P(c_size_t)]),
    "fr_audio_stream_release": (None, [handle]),
}

progress_fn = ctypes.CFUNCTYPE(c_int32, c_void_p, c_char_p, c_uint64, c_uint64)

_OFFLINE_FUNCTIONS = {
    "fr_offline_build": (status, [c_char_p, progress_fn, c_void_p]),
    "fr_offline_photo": (status, [c_char_p, progress_fn, c_void_p]),
    "fr_offline_default_head": (status, [c_char_p, progress_fn, c_void_p]),
    "fr_offline_convert": (status, [c_char_p, progress_fn, c_void_p]),
    "fr_offline_report": (status, [c_char_p, c_size_t, P(c_size_t)]),
}

tts_audio_fn = ctypes.CFUNCTYPE(c_int32, c_void_p, P(c_float), c_size_t)
tts_phoneme_fn = ctypes.CFUNCTYPE(c_int32, c_void_p, P(Phoneme))

_TTS_FUNCTIONS = {
    "fr_tts_synthesize": (status, [c_char_p, c_char_p, P(handle)]),
    "fr_tts_synthesize_streaming": (status, [c_char_p, c_char_p, P(c_int32), tts_audio_fn, tts_phoneme_fn, c_void_p]),
    "fr_tts_align": (status, [float_p, c_size_t, c_int32, c_char_p, c_char_p, P(handle)]),
    "fr_tts_voices": (status, [c_char_p, c_size_t, P(c_size_t)]),
}


def _candidates(file_name):
    if os.environ.get("FACERIG_LIBRARY") and file_name == "libfacerig.so.0":
        yield os.environ["FACERIG_LIBRARY"]
    for folder in (os.environ.get("FACERIG_LIBRARY_DIR"), os.path.dirname(os.path.abspath(__file__))):
        if folder:
            path = os.path.join(folder, file_name)
            if os.path.exists(path):
                yield path
    yield file_name  # the system's library path


def _translated(function):
    """`function`, raising the ClosedError a closed handle's conversion raised (ctypes wraps it)."""
    def call(*args):
        try:
            return function(*args)
        except ctypes.ArgumentError as error:
            kind, _, message = str(error).partition(": ClosedError: ")
            if message:
                raise ClosedError(message, "FR_ERROR_INVALID_ARGUMENT") from None
            raise
    call.__name__ = call.__qualname__ = function.__name__
    return call


def _open(file_name, functions, near=None):
    errors = []
    candidates = list(_candidates(file_name))
    if near:  # beside libfacerig first
        candidates.insert(0, os.path.join(os.path.dirname(near), file_name))
    for candidate in candidates:
        try:
            library = ctypes.CDLL(candidate)
        except OSError as error:
            errors.append(str(error))
            continue
        calls = types.SimpleNamespace()
        for name, (restype, argtypes) in functions.items():
            function = getattr(library, name)
            function.restype = restype
            function.argtypes = argtypes
            setattr(calls, name, _translated(function))
        return calls, candidate
    raise OSError(f"cannot load {file_name}: set FACERIG_LIBRARY_DIR to the folder holding it "
                  f"(build/lib of a facerig build). Tried: " + "; ".join(errors))


lib, library_path = _open("libfacerig.so.0", _FUNCTIONS)
if lib.fr_abi_version() >> 16 != ABI_VERSION_MAJOR or (lib.fr_abi_version() & 0xFFFF) < ABI_VERSION_MINOR:
    raise OSError(f"{library_path} has ABI version {lib.fr_abi_version():#x}; this package needs "
                  f"{ABI_VERSION_MAJOR}.{ABI_VERSION_MINOR} or a later minor")

_tts = None
_offline = None


def tts_library():
    """libfacerig_espeak, loaded on first use."""
    global _tts
    if _tts is None:
        _tts, _ = _open("libfacerig_espeak.so.0", _TTS_FUNCTIONS, near=library_path)
    return _tts


def offline_library():
    """libfacerig_offline, loaded on first use."""
    global _offline
    if _offline is None:
        _offline, _ = _open("libfacerig_offline.so.0", _OFFLINE_FUNCTIONS, near=library_path)
    return _offline
