"""The `facerig` command's offline tools as calls (libfacerig_offline; GPL as a whole, see docs/licences.md).

Each takes the command's options as keyword arguments (their long names, '_'
for '-': obj_dir="..." is --obj-dir; output="x.glb" is -o; True is a flag) and
returns the command's JSON report as a dict. `progress(stage, done, total)`,
if given, is called as the command goes; returning True stops it
(CancelledError, nothing written).
"""
import ctypes
import json

from . import _native
from .status import check


def _run(function_name, inputs, progress, options):
    document = {("o" if key == "output" else key.replace("_", "-")): value for key, value in options.items()}
    if inputs:
        document["inputs"] = [str(i) for i in inputs]
    for key, value in document.items():
        if hasattr(value, "__fspath__"):
            document[key] = str(value)
    library = _native.offline_library()
    raised = []

    def report_progress(_user, stage, done, total):
        try:
            return 1 if progress(stage.decode(), done, total) else 0
        except BaseException as error:  # stop the command, raise it here afterwards
            raised.append(error)
            return 1

    callback = _native.progress_fn(report_progress) if progress else _native.progress_fn()
    status = getattr(library, function_name)(json.dumps(document).encode(), callback, None)
    if raised:
        raise raised[0]
    check(status)
    needed = ctypes.c_size_t()
    library.fr_offline_report(None, 0, ctypes.byref(needed))
    buffer = ctypes.create_string_buffer(needed.value)
    check(library.fr_offline_report(buffer, len(buffer), ctypes.byref(needed)))
    return json.loads(buffer.value.decode("utf-8"))


def build(progress=None, **options):
    """`facerig build`: template=, target=, output=, and the command's other options."""
    return _run("fr_offline_build", [], progress, options)


def photo(image, progress=None, **options):
    """`facerig photo IMAGE`: output=, template=, frig=, ..."""
    return _run("fr_offline_photo", [image], progress, options)


def default_head(out_dir, progress=None, **options):
    """`facerig default-head OUT_DIR`: the built-in head (.glb, .frig, descriptor)."""
    return _run("fr_offline_default_head", [out_dir], progress, options)


def convert(source, destination, progress=None, **options):
    """`facerig convert IN OUT`: formats by extension."""
    return _run("fr_offline_convert", [source, destination], progress, options)
