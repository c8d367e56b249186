"""numpy arrays passed to C without copies: float32, C-contiguous, checked here."""
import ctypes

import numpy as np

from .errors import InvalidArgumentError


def float_input(values, name):
    """`values` as a contiguous float32 array (a copy only when it is not one already)."""
    return np.ascontiguousarray(values, dtype=np.float32)


def float_output(out, shape, name):
    """A new float32 array of `shape`, or `out` checked for dtype and layout (its size is left to C)."""
    if out is None:
        return np.empty(shape, dtype=np.float32)
    if not isinstance(out, np.ndarray) or out.dtype != np.float32 or not out.flags.c_contiguous \
            or not out.flags.writeable:
        raise InvalidArgumentError(f"{name} must be a writeable, C-contiguous float32 numpy array",
                                   "FR_ERROR_INVALID_ARGUMENT")
    return out


def pointer(array):
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_float))
