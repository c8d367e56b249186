"""The Python binding's rigs: blends equal the C ABI's, arrays are shared, errors raise with the message."""
import os

import numpy as np
import pytest

import facerig
from test_speech import TRACK


def test_rig_info_and_mesh(rig):
    assert rig.vertex_count > 10000 and rig.shape_count > 50
    assert rig.shape_names[rig.find_shape("jawOpen")] == "jawOpen"
    positions, normals = rig.neutral()
    assert positions.shape == (rig.vertex_count, 3) and np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-4)
    assert rig.triangles().max() < rig.vertex_count
    assert rig.parts[0]["name"] == "skin"


def test_blend_and_weights_equal_the_c_consumers(rig):
    """The C consumer (hosts/c/tests/consumer.c) wrote frame 20 at 60 fps of the same track."""
    raw = np.fromfile(os.environ["FACERIG_REFERENCE"], dtype=np.float32)
    c_weights, c_positions = raw[:rig.shape_count], raw[rig.shape_count:].reshape(-1, 3)
    character = facerig.Character(rig)
    character.speak(facerig.Speech.from_track(TRACK))
    for frame in range(21):
        weights = character.update(frame / 60.0)
    assert np.array_equal(weights, c_weights)
    assert np.count_nonzero(weights) >= 2  # the mouth open on "A:"
    assert np.array_equal(rig.blend(weights), c_positions)


def test_blend_writes_into_the_callers_array_without_copies(rig):
    out = np.zeros((rig.vertex_count, 3), np.float32)
    weights = np.zeros(rig.shape_count, np.float32)
    weights[rig.find_shape("jawOpen")] = 1.0
    assert rig.blend(weights, out=out) is out
    character = facerig.Character(rig)
    mine = np.empty(rig.shape_count, np.float32)
    assert character.update(0.1, out=mine) is mine
    assert not np.array_equal(out, rig.neutral()[0])
    positions, normals = rig.blend(weights, normal_mode="recompute")
    assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-4)


def test_errors_raise_with_the_message(rig, head_path, tmp_path):
    with pytest.raises(facerig.FileError, match="no_such_head.glb"):
        facerig.Rig(tmp_path / "no_such_head.glb")
    glb = open(os.path.splitext(head_path)[0] + ".glb", "rb").read()
    with pytest.raises(facerig.FormatError, match="head.glb"):
        facerig.Rig.from_bytes(glb[: len(glb) // 2], "head.glb")
    truncated = tmp_path / "truncated.glb"
    truncated.write_bytes(glb[:1000])
    with pytest.raises(facerig.FormatError, match="truncated.glb"):
        facerig.Rig(truncated)
    with pytest.raises(facerig.BufferTooSmallError, match="need room for"):
        rig.blend(np.zeros(rig.shape_count), out=np.zeros((10, 3), np.float32))
    with pytest.raises(facerig.InvalidArgumentError, match="weight_count"):
        rig.blend(np.zeros(3))
    with pytest.raises(facerig.InvalidArgumentError, match="float32"):
        rig.blend(np.zeros(rig.shape_count), out=np.zeros((rig.vertex_count, 3)))
    with pytest.raises(facerig.NotFoundError, match="noSuchShape"):
        rig.find_shape("noSuchShape")
    character = facerig.Character(rig)
    with pytest.raises(facerig.BufferTooSmallError):
        character.update(0.0, out=np.zeros(3, np.float32))
    with pytest.raises(facerig.StateError, match="BeginLine"):
        character.push_phoneme(facerig.Phoneme(0.0, 0.1, "p"))
    with pytest.raises(facerig.FormatError, match="version"):
        facerig.Speech.from_track('{"phonemes": []}')
    character.close()
    with pytest.raises(facerig.ClosedError, match="closed"):
        character.update(0.0)


def test_a_rig_without_shapes_blends_and_talks_silently():
    """Found by the capi fuzzer: a rig with no shapes takes NULL weights (nothing to point at)."""
    seed = os.path.join(os.path.dirname(__file__), "..", "..", "..", "fuzz", "seeds", "capi", "grid_uv.glb")
    rig = facerig.Rig.from_bytes(open(seed, "rb").read(), "grid_uv.glb")
    assert rig.shape_count == 0
    positions = rig.blend(np.zeros(0, np.float32))
    assert np.array_equal(positions, rig.neutral()[0])
    assert facerig.Character(rig).update(0.5).size == 0


def test_a_glb_from_bytes_may_not_name_files(tmp_path, monkeypatch):
    """A GLB from memory has no folder: a buffer naming a file is refused, not read from the working folder."""
    import struct
    (tmp_path / "x.bin").write_bytes(bytes(12))
    monkeypatch.chdir(tmp_path)
    document = b'{"asset": {"version": "2.0"}, "buffers": [{"uri": "x.bin", "byteLength": 12}]}'
    document += b" " * (-len(document) % 4)
    glb = b"glTF" + struct.pack("<II", 2, 12 + 8 + len(document)) + struct.pack("<I", len(document)) + b"JSON" + document
    with pytest.raises(facerig.FileError, match=r"buffers\[0\]\.uri names a file"):
        facerig.Rig.from_bytes(glb, "external.glb")


def test_a_character_keeps_its_rig_alive(head_path):
    rig = facerig.Rig(head_path)
    character = facerig.Character(rig)
    rig.close()
    with pytest.raises(facerig.ClosedError):
        rig.blend(np.zeros(3))
    character.speak(facerig.Speech.from_track(TRACK))
    assert np.isfinite(character.update(0.3)).all()


def _dense_deltas(rig):
    """Each shape's dense deltas, from one-hot blends."""
    neutral, _ = rig.neutral()
    deltas = np.empty((rig.shape_count, rig.vertex_count, 3), np.float32)
    weights = np.zeros(rig.shape_count, np.float32)
    for i in range(rig.shape_count):
        weights[:] = 0.0
        weights[i] = 1.0
        deltas[i] = rig.blend(weights) - neutral
    return neutral, deltas


def test_a_rig_from_arrays_blends_and_speaks_as_the_loaded_one(rig):
    """What the Blender add-on does with a mesh's shape keys (fr_rig_create)."""
    neutral, deltas = _dense_deltas(rig)
    made = facerig.Rig.from_arrays(neutral, rig.triangles(), rig.shape_names, deltas)
    assert (made.vertex_count, made.triangle_count, made.shape_names) == \
        (rig.vertex_count, rig.triangle_count, rig.shape_names)
    weights = np.zeros(rig.shape_count, np.float32)
    weights[[rig.find_shape("jawOpen"), rig.find_shape("eyeBlinkLeft")]] = (0.7, 0.4)
    assert np.allclose(made.blend(weights), rig.blend(weights), atol=1e-5 * rig.bounding_diagonal)
    speech = facerig.Speech.from_track(TRACK)
    loaded, created = facerig.Character(rig, seed=5), facerig.Character(made, seed=5)
    loaded.speak(speech)
    created.speak(speech)
    for t in np.arange(0.0, 1.0, 1 / 30):
        assert np.array_equal(loaded.update(t), created.update(t))


def test_a_rig_from_bad_arrays_is_refused_with_the_reason(rig):
    neutral, _ = rig.neutral()
    triangles = rig.triangles()
    no_deltas = np.zeros((2, rig.vertex_count, 3), np.float32)
    with pytest.raises(facerig.InvalidArgumentError, match="'jawOpen' appears twice"):
        facerig.Rig.from_arrays(neutral, triangles, ["jawOpen", "jawOpen"], no_deltas)
    bad = triangles.copy()
    bad[3, 1] = rig.vertex_count
    with pytest.raises(facerig.InvalidArgumentError, match="triangle 3"):
        facerig.Rig.from_arrays(neutral, bad)
    nan = neutral.copy()
    nan[7, 2] = np.nan
    with pytest.raises(facerig.InvalidArgumentError, match="position value 23 is NaN"):
        facerig.Rig.from_arrays(nan, triangles)
    with pytest.raises(facerig.InvalidArgumentError, match="deltas holds"):
        facerig.Rig.from_arrays(neutral, triangles, ["jawOpen"], no_deltas)
