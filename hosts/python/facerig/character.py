"""Characters: speech, emotions, blinks and gaze -> rig weights per frame."""
import ctypes

from . import _native
from ._arrays import float_output, pointer
from ._handle import Handle, new_handle
from .status import check

EMOTIONS = ("joy", "sadness", "fear", "anger", "surprise", "disgust")
VISEMES = ("sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou")


class Character(Handle):
    """A talking character on a Rig, driven by your clock (the audio playback position).

    Per frame, update(time) returns the rig weights (a float32 array, one per
    shape; pass `out` to fill your own array without allocating), for
    Rig.blend or your engine's morph targets.
    """

    _release = _native.lib.fr_character_release

    def __init__(self, rig, seed=0, jaw_intensity=1.0, lip_intensity=1.0, key_capacity=8192, blinks=True,
                 gaze=True):
        options = _native.CharacterOptions()
        check(_native.lib.fr_character_default_options(ctypes.byref(options)))
        options.seed, options.jaw_intensity, options.lip_intensity = seed, jaw_intensity, lip_intensity
        options.key_capacity, options.blinks, options.gaze = key_capacity, int(blinks), int(gaze)
        pointer_ = new_handle()
        check(_native.lib.fr_character_create(rig, ctypes.byref(options), ctypes.byref(pointer_)))
        super().__init__(pointer_)
        self.shape_count = rig.shape_count

    def speak(self, speech, start_time=0.0):
        """Says a whole Speech line whose time 0 is `start_time` on the clock (replacing any line)."""
        check(_native.lib.fr_character_speak(self, speech, start_time))

    def begin_line(self, start_time=0.0):
        """Streaming: starts an empty line; push_phoneme() its phonemes as they arrive; end_line()."""
        check(_native.lib.fr_character_begin_line(self, start_time))

    def push_phoneme(self, phoneme):
        check(_native.lib.fr_character_push_phoneme(self, ctypes.byref(phoneme.to_c())))

    def end_line(self):
        check(_native.lib.fr_character_end_line(self))

    def stop(self):
        """Stops speaking at once; the mouth relaxes over the next frames."""
        check(_native.lib.fr_character_stop(self))

    def set_emotion(self, emotion, target):
        """Emotion ("joy", "sadness", "fear", "anger", "surprise", "disgust") toward `target` in [0, 1]."""
        check(_native.lib.fr_character_set_emotion(self, EMOTIONS.index(emotion), target))

    def set_behaviour(self, blinks=True, gaze=True):
        """Blinks and idle gaze on or off."""
        check(_native.lib.fr_character_set_behaviour(self, int(blinks), int(gaze)))

    def update(self, time, out=None):
        """The rig weights at `time` (seconds), in `out` if given (float32, >= shape_count)."""
        out = float_output(out, (self.shape_count,), "out")
        check(_native.lib.fr_character_update(self, time, pointer(out), out.size))
        return out

    @property
    def state(self):
        """What the last update found: talking, at_pause, viseme, blinks, gaze, phoneme."""
        s = _native.CharacterState()
        check(_native.lib.fr_character_get_state(self, ctypes.byref(s)))
        return {"talking": bool(s.talking), "at_pause": bool(s.at_pause), "viseme": VISEMES[s.viseme],
                "blink": (s.blink_left, s.blink_right), "gaze": (s.gaze_x, s.gaze_y),
                "phoneme": s.phoneme.decode()}
