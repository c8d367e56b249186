"""Shape keys the add-on writes, and the record of what it added (for re-building and Clear).

The record is the object's custom property "facerig": {"shapes": names it
added, "basis": 1 when it added the Basis key too, "parts": the other objects
built with it, ...}. Keys of the user's are never written or removed.
"""
import numpy as np

from .jobs import UserError
from .mesh_export import basis_positions

RECORD = "facerig"


def record(obj):
    """The object's record as a plain dict ({} when the add-on added nothing)."""
    stored = obj.get(RECORD)
    return stored.to_dict() if stored is not None else {}


def save_record(obj, values):
    if values:
        obj[RECORD] = values
    elif RECORD in obj:
        del obj[RECORD]


def owned_shapes(obj):
    return list(record(obj).get("shapes", []))


def check_names_free(obj, names):
    """UserError when the object has keys of these names that the add-on did not write."""
    keys = obj.data.shape_keys
    if keys is None:
        return
    owned = set(owned_shapes(obj))
    taken = [name for name in names if name in keys.key_blocks and name not in owned]
    if taken:
        shown = ", ".join(taken[:5]) + (f" and {len(taken) - 5} more" if len(taken) > 5 else "")
        raise UserError(f"'{obj.name}' already has shape keys named {shown} that facerig did not make: "
                        "rename or delete them first")


def write_shapes(obj, names, deltas, moving_only=False):
    """Shape keys `names` on obj: its Basis plus deltas[i] ((n, 3), object space). With moving_only,
    shapes that leave every vertex in place are skipped. Returns the names written."""
    mesh = obj.data
    values = record(obj)
    if mesh.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
        values["basis"] = 1
    basis = basis_positions(mesh)
    scale = float(np.ptp(basis, axis=0).max()) if len(basis) else 0.0
    written = []
    for name, delta in zip(names, deltas):
        if moving_only and np.abs(delta).max(initial=0.0) <= 1e-6 * scale:
            continue
        key = mesh.shape_keys.key_blocks.get(name) or obj.shape_key_add(name=name, from_mix=False)
        key.data.foreach_set("co", (basis + delta).ravel())
        written.append(name)
    values["shapes"] = list(dict.fromkeys(owned_shapes(obj) + written))
    save_record(obj, values)
    mesh.update()
    return written


def remove_shapes(obj):
    """Removes the keys the add-on added (and the Basis, when it added it and no other key is left)."""
    values = record(obj)
    keys = obj.data.shape_keys
    if keys is not None:
        action = keys.animation_data.action if keys.animation_data else None
        for name in values.get("shapes", []):
            key = keys.key_blocks.get(name)
            if key is not None:
                obj.shape_key_remove(key)
            fcurve = action.fcurves.find(f'key_blocks["{name}"].value') if action else None
            if fcurve is not None:  # it would animate nothing
                action.fcurves.remove(fcurve)
        keys = obj.data.shape_keys
        if values.get("basis") and keys is not None and len(keys.key_blocks) == 1:
            obj.shape_key_remove(keys.key_blocks[0])
    for name in ("shapes", "basis", "parts", "template", "left_out"):
        values.pop(name, None)
    save_record(obj, values)
