"""Rigs: load, inspect, blend into numpy arrays."""
import ctypes
import os

import numpy as np

from . import _native
from ._arrays import float_input, float_output, pointer
from ._handle import Handle, new_handle
from .errors import InvalidArgumentError
from .status import check

NORMALS = {"none": 0, "blend": 1, "recompute": 2}


class Rig(Handle):
    """A loaded rig: a neutral mesh plus named, sparse blend shapes. Immutable.

    Rig(path) loads a .glb, .gltf, .frig or .obj file; Rig.from_bytes(data)
    the bytes of a .glb or .frig; Rig.from_arrays(positions, triangles,
    shape_names, deltas) a mesh and its shapes. Characters made from a rig
    keep it alive.
    """

    _release = _native.lib.fr_rig_release

    def __init__(self, path):
        pointer_ = new_handle()
        check(_native.lib.fr_rig_load_file(os.fsencode(path), ctypes.byref(pointer_)))
        super().__init__(pointer_)
        self._read_info()

    @classmethod
    def from_bytes(cls, data, name="<memory>"):
        """A rig from the bytes of a .glb or .frig (`name` only for messages)."""
        data = bytes(data)
        pointer_ = new_handle()
        check(_native.lib.fr_rig_load_bytes(data, len(data), name.encode(), ctypes.byref(pointer_)))
        rig = cls.__new__(cls)
        Handle.__init__(rig, pointer_)
        rig._read_info()
        return rig

    @classmethod
    def from_arrays(cls, positions, triangles, shape_names=(), deltas=None):
        """A rig from arrays (e.g. a 3D application's mesh and shape keys): positions (n, 3),
        triangles (t, 3) vertex indices, and per name in shape_names its dense deltas,
        deltas[i] of shape (n, 3)."""
        positions = float_input(positions, "positions").reshape(-1, 3)
        triangles = np.ascontiguousarray(triangles, dtype=np.uint32).reshape(-1, 3)
        names = [name.encode("utf-8") for name in shape_names]
        deltas = float_input(deltas if deltas is not None else np.empty((0, len(positions), 3)), "deltas")
        if deltas.size != len(names) * positions.size:
            raise InvalidArgumentError(f"deltas holds {deltas.size} floats, not {len(names)} shapes x "
                                       f"{len(positions)} vertices x 3", "FR_ERROR_INVALID_ARGUMENT")
        c_names = (ctypes.c_char_p * len(names))(*names)
        pointer_ = new_handle()
        check(_native.lib.fr_rig_create(pointer(positions), len(positions),
                                        triangles.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)), len(triangles),
                                        c_names, pointer(deltas) if deltas.size else None, len(names),
                                        ctypes.byref(pointer_)))
        rig = cls.__new__(cls)
        Handle.__init__(rig, pointer_)
        rig._read_info()
        return rig

    def _read_info(self):
        info = _native.RigInfo()
        check(_native.lib.fr_rig_get_info(self, ctypes.byref(info)))
        self.vertex_count = info.vertex_count
        self.triangle_count = info.triangle_count
        self.shape_count = info.shape_count
        self.part_count = info.part_count
        self.has_uvs = bool(info.has_uvs)
        self.has_normal_deltas = bool(info.has_normal_deltas)
        self.units = ("unknown", "mm", "cm", "m")[info.units]
        self.up_axis = ("y", "z")[info.up_axis]
        self.bounding_diagonal = info.bounding_diagonal
        self.shape_names = [self._name(_native.lib.fr_rig_shape_name, i) for i in range(self.shape_count)]

    def _name(self, function, index):
        needed = ctypes.c_size_t()
        buffer = ctypes.create_string_buffer(64)
        status = function(self, index, buffer, len(buffer), ctypes.byref(needed))
        if status == 2:  # FR_ERROR_BUFFER_TOO_SMALL: the size it needs is in `needed`
            buffer = ctypes.create_string_buffer(needed.value)
            status = function(self, index, buffer, len(buffer), ctypes.byref(needed))
        check(status)
        return buffer.value.decode("utf-8")

    def find_shape(self, name):
        """The index of the shape named `name`; NotFoundError if none."""
        index = ctypes.c_uint32()
        check(_native.lib.fr_rig_find_shape(self, name.encode("utf-8"), ctypes.byref(index)))
        return index.value

    @property
    def parts(self):
        """[{name, first_triangle, triangle_count, first_vertex, vertex_count, material}]."""
        parts = []
        for i in range(self.part_count):
            info = _native.PartInfo()
            check(_native.lib.fr_rig_part_info(self, i, ctypes.byref(info)))
            parts.append({"name": self._name(_native.lib.fr_rig_part_name, i),
                          **{field: getattr(info, field) for field, _ in _native.PartInfo._fields_}})
        return parts

    def neutral(self):
        """(positions, normals) of the neutral mesh, each a (vertex_count, 3) float32 array."""
        positions = np.empty((self.vertex_count, 3), np.float32)
        normals = np.empty((self.vertex_count, 3), np.float32)
        check(_native.lib.fr_rig_neutral(self, pointer(positions), pointer(normals), self.vertex_count, None))
        return positions, normals

    def triangles(self):
        """(triangle_count, 3) uint32 vertex indices."""
        triangles = np.empty((self.triangle_count, 3), np.uint32)
        check(_native.lib.fr_rig_triangles(self, triangles.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
                                           self.triangle_count, None))
        return triangles

    def uvs(self):
        """(vertex_count, 2) float32 texture coordinates; NotFoundError when the rig has none."""
        uvs = np.empty((self.vertex_count, 2), np.float32)
        check(_native.lib.fr_rig_uvs(self, pointer(uvs), self.vertex_count, None))
        return uvs

    def blend(self, weights, out=None, normals=None, normal_mode="none"):
        """Positions for `weights` (one per shape): neutral + sum of weight * shape.

        Writes into `out` (and `normals`, for normal_mode "blend" or "recompute")
        when given: float32, C-contiguous, (vertex_count, 3), filled in place
        without copies. Returns `out` (or (out, normals) with a normal mode).
        """
        weights = float_input(weights, "weights")
        out = float_output(out, (self.vertex_count, 3), "out")
        mode = NORMALS[normal_mode]
        if mode and normals is None:
            normals = np.empty((self.vertex_count, 3), np.float32)
        if mode:
            normals = float_output(normals, (self.vertex_count, 3), "normals")
            if normals.size != out.size:
                raise InvalidArgumentError("normals and out must have the same size", "FR_ERROR_INVALID_ARGUMENT")
        check(_native.lib.fr_rig_blend(self, pointer(weights), weights.size, mode, pointer(out),
                                       pointer(normals) if mode else None, out.size // 3))
        return (out, normals) if mode else out
