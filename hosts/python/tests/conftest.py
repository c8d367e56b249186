"""Paths from ctest (hosts/python/CMakeLists.txt): the built-in head, the C consumer's reference frame."""
import os

import numpy as np
import pytest


@pytest.fixture(scope="session")
def head_path():
    return os.environ["FACERIG_DEFAULT_HEAD"]


@pytest.fixture(scope="session")
def rig(head_path):
    import facerig
    return facerig.Rig(head_path)


def lip_pair(rig):
    """The inner-lip contact on the midline (as hosts/c/tests/consumer.c finds it): of the skin's
    midline vertices, the nearest pair at rest of one jawOpen carries and one it leaves."""
    neutral, _ = rig.neutral()
    weights = np.zeros(rig.shape_count, np.float32)
    weights[rig.find_shape("jawOpen")] = 1.0
    moved = np.linalg.norm(rig.blend(weights) - neutral, axis=1)
    skin = rig.parts[0]
    span = np.arange(skin["first_vertex"], skin["first_vertex"] + skin["vertex_count"])
    midline = span[np.abs(neutral[span, 0]) <= 0.01 * rig.bounding_diagonal]
    lower = midline[moved[midline] >= 0.5 * moved.max()]
    upper = midline[moved[midline] <= 0.1 * moved.max()]
    distances = np.linalg.norm(neutral[lower][:, None, :] - neutral[upper][None, :, :], axis=2)
    i, j = np.unravel_index(np.argmin(distances), distances.shape)
    return upper[j], lower[i]
