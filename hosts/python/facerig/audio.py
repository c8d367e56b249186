"""Phonemes from audio that arrives in chunks (rough mode or aligned to a transcript)."""
import ctypes

from . import _native
from ._arrays import float_input, pointer
from ._handle import Handle, new_handle
from .status import check
from .speech import read_phonemes


class AudioStream(Handle):
    """AudioStream.rough(rate): a coarse mouth from audio alone; AudioStream.aligned(reference):
    the transcript's phonemes (reference = facerig.tts.synthesize(text, voice)) timed on a
    recording at the reference's rate. push(samples) returns the phonemes made final, to
    push into a Character; finish() the rest."""

    _release = _native.lib.fr_audio_stream_release

    @classmethod
    def rough(cls, sample_rate):
        pointer_ = new_handle()
        check(_native.lib.fr_audio_stream_create_rough(sample_rate, ctypes.byref(pointer_)))
        return cls(pointer_)

    @classmethod
    def aligned(cls, reference):
        pointer_ = new_handle()
        check(_native.lib.fr_audio_stream_create_aligned(reference, ctypes.byref(pointer_)))
        return cls(pointer_)

    def _read(self):
        phonemes = []
        while True:
            chunk = read_phonemes(_native.lib.fr_audio_stream_read, self)
            if not chunk:
                return phonemes
            phonemes += chunk

    def push(self, samples):
        """Mono float samples in [-1, 1]; returns the phonemes made final by them."""
        samples = float_input(samples, "samples")
        check(_native.lib.fr_audio_stream_push(self, pointer(samples), samples.size))
        return self._read()

    def finish(self):
        """The end of the audio: the remaining phonemes."""
        check(_native.lib.fr_audio_stream_finish(self))
        return self._read()
