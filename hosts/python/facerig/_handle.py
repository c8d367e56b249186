"""Ownership of a C handle: released by close(), by `with`, or when collected."""
import ctypes

from .errors import ClosedError


class Handle:
    """Base of the objects that own a facerig handle."""

    _release = None  # the fr_*_release function, set by subclasses

    def __init__(self, pointer):
        self._pointer = pointer

    @property
    def _as_parameter_(self):
        """The handle for ctypes calls; ClosedError once closed."""
        if not self._pointer:
            raise ClosedError(f"this {type(self).__name__} was closed", "FR_ERROR_INVALID_ARGUMENT")
        return self._pointer

    @property
    def closed(self):
        return not self._pointer

    def close(self):
        """Releases the handle now (idempotent)."""
        pointer, self._pointer = self._pointer, None
        if pointer and type(self)._release is not None:
            type(self)._release(pointer)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown
            pass


def new_handle():
    return ctypes.c_void_p()
