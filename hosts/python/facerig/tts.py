"""Text-to-speech and recorded-speech alignment with espeak-ng (libfacerig_espeak, GPL-3)."""
import ctypes

from . import _native
from ._arrays import float_input, pointer
from ._handle import new_handle
from .errors import check
from .speech import Speech


def synthesize(text, voice="en-us"):
    """A Speech with espeak-ng's audio (22050 Hz) and its exactly timed phonemes."""
    pointer_ = new_handle()
    check(_native.tts_library().fr_tts_synthesize(text.encode("utf-8"), voice.encode(), ctypes.byref(pointer_)))
    return Speech._wrap(pointer_)


def align(samples, sample_rate, transcript, voice="en-us"):
    """The transcript's phonemes timed on a recording (mono float samples), as a Speech holding it."""
    samples = float_input(samples, "samples")
    pointer_ = new_handle()
    check(_native.tts_library().fr_tts_align(pointer(samples), samples.size, sample_rate,
                                             transcript.encode("utf-8"), voice.encode(), ctypes.byref(pointer_)))
    return Speech._wrap(pointer_)


def voices():
    """The installed espeak-ng voices' language names."""
    library = _native.tts_library()
    needed = ctypes.c_size_t()
    library.fr_tts_voices(None, 0, ctypes.byref(needed))
    buffer = ctypes.create_string_buffer(needed.value)
    check(library.fr_tts_voices(buffer, len(buffer), ctypes.byref(needed)))
    return buffer.value.decode().split()
