"""Plain per-window reference of the gravity feature frame (one window at a time, no batching).

Written from the definition in :mod:`gaitml.features._frame` with ``numpy.linalg.eigh`` on
one 3 x 3 matrix per window; used to check the vectorised rotations and features.
"""

from __future__ import annotations

import numpy as np

from tests.reference.features import reference_features


def reference_rotation(window: np.ndarray) -> np.ndarray:
    """(L, 3) acceleration samples -> (3, 3) rotation, rows x (right), y (forward), z (up)."""
    mean = window.mean(axis=0)
    z = mean / np.linalg.norm(mean)
    d = window - mean
    vertical = d @ z
    horizontal = d - np.outer(vertical, z)
    cov = horizontal.T @ horizontal / len(window)
    _, vecs = np.linalg.eigh(cov)
    y = vecs[:, -1] - z * (vecs[:, -1] @ z)
    y /= np.linalg.norm(y)
    along = d @ y
    if np.sum(along[:-1] * np.diff(vertical)) < 0:  # along-axis acceleration follows d/dt of the vertical one
        y = -y
    return np.array([np.cross(y, z), y, z])


def reference_gravity_features(acc, gyr, starts, length: int, subset: str = "all52") -> np.ndarray:
    """Features of every window in its own gravity frame, window by window."""
    rows = []
    for s in starts:
        a = acc[s : s + length]
        r = reference_rotation(a)
        g = None if gyr is None else gyr[s : s + length] @ r.T
        rows.append(reference_features(a @ r.T, g, [0], length, subset)[0])
    return np.array(rows)
