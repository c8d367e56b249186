"""The templates a build can use: an ICT-FaceKit folder, or facerig's built-in head.

The ICT-FaceKit folder comes from the operator, else the add-on's
preference, else $FACERIG_ICT_DIR, else ../shared/data/ict-facekit beside the
source tree the add-on runs from. The built-in head is $FACERIG_DEFAULT_HEAD
(a build's build/data/default_head.frig), else made once by
facerig.offline.default_head into Blender's user data folder (a few seconds).
"""
import os
from dataclasses import dataclass, field
from typing import Callable

import bpy

from . import library
from .jobs import UserError

TEMPLATE_ITEMS = [
    ("ICT", "ICT-FaceKit", "The ICT-FaceKit template (a folder of OBJs, see the add-on's preferences)"),
    ("BUILTIN", "Built-in Head", "facerig's built-in head, made by facerig itself"),
]

_HERE = os.path.dirname(os.path.realpath(__file__))  # through a link into Blender's add-on folder
_SOURCE_TREE_ICT = os.path.normpath(os.path.join(_HERE, "..", "..", "..", "..", "shared", "data", "ict-facekit"))


@dataclass
class Template:
    label: str
    path: Callable  # path(progress) -> the template's path (may make the built-in head first)
    options: dict = field(default_factory=dict)  # more options for facerig.offline.build


def _preference(name):
    addon = bpy.context.preferences.addons.get(__package__)
    return getattr(addon.preferences, name) if addon else ""


def ict_folder(folder=""):
    """The ICT-FaceKit folder to use, or '' when none is set or found."""
    for candidate in (folder, _preference("ict_folder"), os.environ.get("FACERIG_ICT_DIR", "")):
        if candidate:
            return library.bpy_path(candidate)
    return _SOURCE_TREE_ICT if os.path.isdir(_SOURCE_TREE_ICT) else ""


def builtin_head():
    """path(progress) for the built-in head's .frig, made into Blender's user data folder the first
    time (the folder is found here, on the main thread; the head is made on the worker's)."""
    given = os.environ.get("FACERIG_DEFAULT_HEAD", "")
    if given and os.path.isfile(given):
        return lambda progress: given
    folder = os.path.join(bpy.utils.user_resource("DATAFILES", path="facerig", create=True), "default_head")
    frig = os.path.join(folder, "default_head.frig")
    offline = library.module("offline")

    def path(progress):
        if not os.path.isfile(frig):
            offline.default_head(folder, progress=progress)
        return frig
    return path


def resolve(kind, folder=""):
    """The Template for the operator's choice; UserError when the ICT-FaceKit folder is missing."""
    if kind == "BUILTIN":
        return Template("the built-in head", builtin_head())
    path = ict_folder(folder)
    if not path:
        raise UserError("no ICT-FaceKit folder: set it in the add-on's preferences (or the operator's "
                        "ICT-FaceKit Folder), or use the built-in head as template")
    if not os.path.isdir(path):
        raise UserError(f"the ICT-FaceKit folder {path} does not exist")
    if not os.path.isfile(os.path.join(path, "generic_neutral_mesh.obj")):
        raise UserError(f"{path} is not an ICT-FaceKit folder (it has no generic_neutral_mesh.obj)")
    # The zip carries facerig's descriptor of ICT-FaceKit (landmarks, parts): a source build finds its
    # own copy in data/templates, an installed add-on has only this one.
    descriptor = os.path.join(_HERE, "templates", "ict-facekit.template.json")
    options = {"template_info": descriptor} if os.path.isfile(descriptor) else {}
    return Template(f"ICT-FaceKit ({os.path.basename(path.rstrip(os.sep))})", lambda progress: path, options)
