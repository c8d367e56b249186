"""A C ABI status turned into the exception for it, with this thread's message."""
from . import _native
from .errors import (BufferTooSmallError, CancelledError, FacerigError, FailedError, FileError, FormatError,
                     InvalidArgumentError, LimitError, NotFoundError, SpeechError, StateError)


_BY_STATUS = {
    1: InvalidArgumentError, 2: BufferTooSmallError, 3: NotFoundError, 4: FileError, 5: FormatError,
    6: SpeechError, 7: StateError, 8: LimitError, 9: MemoryError, 11: CancelledError, 12: FailedError,
}


def check(status):
    """Raises the exception for a failed status, with this thread's message."""
    if status == 0:
        return
    message = _native.lib.fr_last_error().decode("utf-8", "replace")
    name = _native.lib.fr_status_name(status).decode()
    kind = _BY_STATUS.get(status, FacerigError)
    if kind is MemoryError:
        raise MemoryError(message)
    raise kind(message, name)
