"""Exceptions raised for the C ABI's status codes, carrying its message."""


class FacerigError(Exception):
    """A facerig call failed. `status` is the fr_status name, str() the message."""

    def __init__(self, message, status="FR_ERROR_INTERNAL"):
        super().__init__(message)
        self.status = status


class InvalidArgumentError(FacerigError, ValueError):
    """A bad value: wrong array size or type, NaN, index out of range, ..."""


class BufferTooSmallError(InvalidArgumentError):
    """An output array is smaller than the call needs."""


class NotFoundError(FacerigError, KeyError):
    """No shape or part of that name."""

    def __str__(self):
        return Exception.__str__(self)


class FileError(FacerigError):
    """A file is missing, unreadable or not a regular file."""


class FormatError(FacerigError):
    """Malformed or truncated data; the message names the file and place."""


class SpeechError(FacerigError):
    """Speech synthesis or alignment failed."""


class StateError(FacerigError):
    """A call out of order, e.g. a phoneme pushed with no line begun."""


class LimitError(FacerigError):
    """A line longer than the character's key capacity."""


class CancelledError(FacerigError):
    """The progress callback asked an offline call to stop; nothing was written."""


class FailedError(FacerigError):
    """An offline command failed on its input (no face found, ...); the message says why."""


class ClosedError(FacerigError):
    """The object was closed (released) and cannot be used any more."""
