"""Text-to-speech and recorded-speech alignment with espeak-ng (libfacerig_espeak, GPL-3)."""
import ctypes

from . import _native
from ._arrays import float_input, pointer
from ._handle import new_handle
from .status import check
from .speech import Phoneme, Speech


def synthesize(text, voice="en-us"):
    """A Speech with espeak-ng's audio (22050 Hz) and its exactly timed phonemes."""
    pointer_ = new_handle()
    check(_native.tts_library().fr_tts_synthesize(text.encode("utf-8"), voice.encode(), ctypes.byref(pointer_)))
    return Speech._wrap(pointer_)


def synthesize_streaming(text, voice="en-us", on_audio=None, on_phoneme=None):
    """Speaks `text`, calling on_audio(samples) with float32 chunks and on_phoneme(Phoneme) as
    espeak-ng makes them (on its worker thread; hand them over, e.g. through a queue). A callback
    returning True stops the line (CancelledError); one that raises stops it and the error is
    raised here. Returns the sample rate."""
    import numpy as np
    raised = []

    def guarded(function, *args):
        try:
            return 1 if function(*args) else 0
        except BaseException as error:
            raised.append(error)
            return 1

    audio = _native.tts_audio_fn(
        lambda _user, samples, count: guarded(on_audio, np.ctypeslib.as_array(samples, (count,)).copy())
    ) if on_audio else _native.tts_audio_fn()
    phoneme = _native.tts_phoneme_fn(
        lambda _user, p: guarded(on_phoneme, Phoneme.from_c(p.contents))
    ) if on_phoneme else _native.tts_phoneme_fn()
    rate = ctypes.c_int32()
    status = _native.tts_library().fr_tts_synthesize_streaming(text.encode("utf-8"), voice.encode(),
                                                               ctypes.byref(rate), audio, phoneme, None)
    if raised:
        raise raised[0]
    check(status)
    return rate.value


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
