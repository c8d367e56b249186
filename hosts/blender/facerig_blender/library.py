"""Where the add-on finds facerig: its Python package (ctypes over the C ABI) and libfacerig*.so.0.

The package is imported on first use, not at registration, so that Blender
starts even without the libraries and a changed preference takes effect:
  1. the copy bundled in the add-on (facerig_blender/facerig, with the .so
     files beside it: the zip of scripts/build-blender-addon.sh);
  2. else hosts/python of the source tree this add-on runs from.
The libraries: the add-on's "Library folder" preference or
$FACERIG_LIBRARY_DIR (a development build's build/lib) first, then beside the
package.
"""
import importlib
import os
import sys

_HERE = os.path.dirname(os.path.realpath(__file__))  # through a link into Blender's add-on folder
_SOURCE_TREE_PACKAGE = os.path.normpath(os.path.join(_HERE, "..", "..", "python"))


class MissingLibraryError(Exception):
    """facerig's package or libraries cannot be loaded (the message says what to set)."""


def _library_dir_preference():
    import bpy
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences.library_dir if addon else ""


def facerig():
    """The facerig package (imported once); MissingLibraryError when it cannot load."""
    library_dir = bpy_path(_library_dir_preference())
    if library_dir:
        os.environ["FACERIG_LIBRARY_DIR"] = library_dir
    try:
        if os.path.isfile(os.path.join(_HERE, "facerig", "__init__.py")):
            return importlib.import_module(__package__ + ".facerig")
        if _SOURCE_TREE_PACKAGE not in sys.path and os.path.isdir(_SOURCE_TREE_PACKAGE):
            sys.path.append(_SOURCE_TREE_PACKAGE)
        return importlib.import_module("facerig")
    except (ImportError, OSError) as error:
        raise MissingLibraryError(
            f"facerig is not available ({error}). Install the add-on zip made by "
            "scripts/build-blender-addon.sh, or set the add-on's Library folder preference to a "
            "facerig build's build/lib") from None


def module(name):
    """facerig.tts or facerig.offline (which load libfacerig_espeak or libfacerig_offline, GPL-3)."""
    package = facerig()
    return importlib.import_module(package.__name__ + "." + name)


def bpy_path(path):
    """A path from a Blender property ('//' relative to the .blend) as an absolute path, or ''."""
    if not path:
        return ""
    import bpy
    return os.path.abspath(bpy.path.abspath(path))
