"""Speech lines (timed phonemes and optional audio) and phoneme conversions."""
import ctypes
import os
from dataclasses import dataclass

import numpy as np

from . import _native
from ._arrays import float_input, pointer
from ._handle import Handle, new_handle
from .status import check


@dataclass
class Phoneme:
    """A timed phoneme: seconds from the line's start, the source's symbol (e.g. espeak-ng "aI", "p")."""
    start: float
    duration: float
    symbol: str
    language: str = ""
    word_start: bool = False

    def to_c(self):
        return _native.Phoneme(self.start, self.duration, self.symbol.encode(), self.language.encode(),
                               int(self.word_start), 0)

    @staticmethod
    def from_c(c):
        return Phoneme(c.start, c.duration, c.symbol.decode(), c.language.decode(), bool(c.word_start))


def read_phonemes(function, handle, capacity=256):
    """Phonemes from a call that takes (handle, buffer, capacity, written)."""
    buffer = (_native.Phoneme * capacity)()
    written = ctypes.c_size_t()
    check(function(handle, buffer, capacity, ctypes.byref(written)))
    return [Phoneme.from_c(buffer[i]) for i in range(written.value)]


class Speech(Handle):
    """A line to speak: timed phonemes and, optionally, its audio. Immutable.

    Speech.from_track(path or JSON text), Speech(phonemes, samples, sample_rate),
    Speech.from_audio(samples, rate) (the rough mode: a coarse mouth from audio
    alone), Speech.from_audio_file(path) (a recording, no phonemes), or
    facerig.tts.synthesize / facerig.tts.align.
    """

    _release = _native.lib.fr_speech_release

    def __init__(self, phonemes=(), samples=None, sample_rate=0):
        c_phonemes = (_native.Phoneme * len(phonemes))(*[p.to_c() for p in phonemes])
        samples = float_input(samples if samples is not None else [], "samples")
        pointer_ = new_handle()
        check(_native.lib.fr_speech_create(c_phonemes, len(phonemes), pointer(samples) if samples.size else None,
                                           samples.size, sample_rate if samples.size else 0,
                                           ctypes.byref(pointer_)))
        super().__init__(pointer_)

    @classmethod
    def _wrap(cls, pointer_):
        speech = cls.__new__(cls)
        Handle.__init__(speech, pointer_)
        return speech

    @classmethod
    def from_track(cls, track):
        """A phoneme-track file (a path) or its JSON text (a str starting with '{', or bytes)."""
        pointer_ = new_handle()
        if isinstance(track, (bytes, bytearray)) or (isinstance(track, str) and track.lstrip().startswith("{")):
            data = track.encode("utf-8") if isinstance(track, str) else bytes(track)
            check(_native.lib.fr_speech_load_track_bytes(data, len(data), ctypes.byref(pointer_)))
        else:
            check(_native.lib.fr_speech_load_track_file(os.fsencode(track), ctypes.byref(pointer_)))
        return cls._wrap(pointer_)

    @classmethod
    def from_audio(cls, samples, sample_rate):
        """The rough mode: phonemes from a recording's loudness and spectrum (no transcript)."""
        samples = float_input(samples, "samples")
        pointer_ = new_handle()
        check(_native.lib.fr_speech_from_audio(pointer(samples), samples.size, sample_rate, ctypes.byref(pointer_)))
        return cls._wrap(pointer_)

    @classmethod
    def from_audio_file(cls, path):
        """A recording read from a file (WAV, FLAC, Ogg/Vorbis, ...; channels mixed to one), with no
        phonemes: its `audio` is what Speech.from_audio and facerig.tts.align take."""
        pointer_ = new_handle()
        check(_native.lib.fr_speech_load_audio_file(os.fsencode(path), ctypes.byref(pointer_)))
        return cls._wrap(pointer_)

    @classmethod
    def aligned(cls, reference, samples, sample_rate):
        """The reference's phonemes (a synthesised rendition of the transcript, with its audio) timed
        on a recording of the same words at the reference's rate, the whole recording at once.
        `fit` on the result: (confidence, tempo, fits), fits under `facerig align`'s rule."""
        samples = float_input(samples, "samples")
        pointer_, fit = new_handle(), _native.AlignmentFit()
        check(_native.lib.fr_speech_align(reference, pointer(samples), samples.size, sample_rate,
                                          ctypes.byref(fit), ctypes.byref(pointer_)))
        speech = cls._wrap(pointer_)
        speech.fit = (fit.confidence, fit.tempo, bool(fit.fits))
        return speech

    @property
    def phonemes(self):
        """The timed phonemes, a list of Phoneme."""
        needed = ctypes.c_size_t()
        status = _native.lib.fr_speech_phonemes(self, None, 0, ctypes.byref(needed))
        if status not in (0, 2):
            check(status)
        buffer = (_native.Phoneme * needed.value)()
        check(_native.lib.fr_speech_phonemes(self, buffer, needed.value, ctypes.byref(needed)))
        return [Phoneme.from_c(p) for p in buffer]

    @property
    def audio(self):
        """(samples, sample_rate): float32 mono samples (empty, 0 when the line has none)."""
        needed, rate = ctypes.c_size_t(), ctypes.c_int32()
        status = _native.lib.fr_speech_audio(self, None, 0, ctypes.byref(needed), ctypes.byref(rate))
        if status not in (0, 2):
            check(status)
        samples = np.empty(needed.value, np.float32)
        check(_native.lib.fr_speech_audio(self, pointer(samples), samples.size, ctypes.byref(needed),
                                          ctypes.byref(rate)))
        return samples, rate.value
