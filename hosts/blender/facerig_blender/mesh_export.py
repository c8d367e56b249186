"""Blender meshes as the OBJ a build reads, and the way back to each object's own vertices.

Blender is Z up with a character facing -Y; facerig reads an OBJ as Y up with
the face toward +Z, as Blender's OBJ exporter writes by default. The OBJ holds
the objects' world positions (their transforms applied, so a rotated or
scaled object builds like the file it came from), the vertices that faces
use, in each object's index order, one object after the other; faces keep
their UVs and material names (the parts a build sees). A built rig keeps the
OBJ's vertices first, in order (seam copies come after them,
facerig/runtime/rig_surface.h), so row `offset + i` of its arrays is vertex
`indices[i]` of an object.
"""
from dataclasses import dataclass

import numpy as np

# (x, y, z) Blender -> (x, z, -y) facerig, and back with its transpose.
TO_FACERIG = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


@dataclass
class ExportedObject:
    name: str
    vertex_count: int     # the object's vertex count when exported
    indices: np.ndarray   # the object's vertices written, in OBJ order
    offset: int           # OBJ vertex of indices[0]
    to_local: np.ndarray  # 3x3: a facerig-frame delta -> the object's local delta


def basis_positions(mesh):
    """(n, 3) float32: the reference shape key's coordinates, or the vertices' when there are no keys."""
    source = mesh.shape_keys.reference_key.data if mesh.shape_keys else mesh.vertices
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    source.foreach_get("co", co)
    return co.reshape(-1, 3)


def _polygons(mesh):
    starts = np.empty(len(mesh.polygons), np.int64)
    totals = np.empty(len(mesh.polygons), np.int64)
    materials = np.empty(len(mesh.polygons), np.int64)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    mesh.polygons.foreach_get("material_index", materials)
    loop_vertices = np.empty(len(mesh.loops), np.int64)
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    return starts, totals, materials, loop_vertices


def _material_name(obj, index):
    slots = obj.material_slots
    material = slots[index].material if index < len(slots) else None
    name = material.name if material else obj.name
    return "_".join(name.split()) or "default"


def _write_object(out, obj, offset, uv_offset):
    """Writes one object's v, vt and f lines; returns its ExportedObject and the UVs written."""
    mesh = obj.data
    starts, totals, materials, loop_vertices = _polygons(mesh)
    used = np.unique(loop_vertices)
    obj_index = np.full(len(mesh.vertices), -1, np.int64)
    obj_index[used] = np.arange(len(used)) + offset + 1  # OBJ indices are 1-based
    world = np.array(obj.matrix_world)
    positions = basis_positions(mesh)[used].astype(np.float64) @ world[:3, :3].T + world[:3, 3]
    positions = positions @ TO_FACERIG.T
    np.savetxt(out, positions, fmt="v %.9g %.9g %.9g")
    uv_layer = mesh.uv_layers.active
    if uv_layer is not None:
        uvs = np.empty(len(mesh.loops) * 2, np.float32)
        uv_layer.data.foreach_get("uv", uvs)
        np.savetxt(out, uvs.reshape(-1, 2), fmt="vt %.9g %.9g")
    corners = [f"{v}/{uv_offset + loop + 1}" if uv_layer is not None else str(v)
               for loop, v in enumerate(obj_index[loop_vertices])]
    material = None
    for start, total, index in zip(starts, totals, materials):
        if index != material:
            material = index
            out.write(f"usemtl {_material_name(obj, index)}\n")
        out.write("f " + " ".join(corners[start:start + total]) + "\n")
    to_local = np.linalg.inv(world[:3, :3]) @ TO_FACERIG.T
    exported = ExportedObject(obj.name, len(mesh.vertices), used, offset, to_local)
    return exported, positions, (len(mesh.loops) if uv_layer is not None else 0)


def write_obj(path, objects):
    """Writes `objects` (meshes) into one OBJ; returns ([ExportedObject], (m, 3) float64 positions written)."""
    exported, written = [], []
    offset = uv_offset = 0
    with open(path, "w", encoding="utf-8") as out:
        out.write("# written by the facerig Blender add-on\n")
        for obj in objects:
            out.write(f"o {'_'.join(obj.name.split()) or 'mesh'}\n")
            item, positions, uv_count = _write_object(out, obj, offset, uv_offset)
            exported.append(item)
            written.append(positions)
            offset += len(positions)
            uv_offset += uv_count
    return exported, np.concatenate(written)


def local_deltas(exported, deltas):
    """(shapes, n, 3) float32 deltas on one object's vertices from (shapes, m, 3) facerig-frame rig
    deltas; vertices no face uses do not move."""
    rows = deltas[:, exported.offset:exported.offset + len(exported.indices)]
    local = np.zeros((deltas.shape[0], exported.vertex_count, 3), np.float32)
    local[:, exported.indices] = rows @ exported.to_local.T
    return local
