"""Window gravity directions and the angle to the nearest training direction."""

from __future__ import annotations

import numpy as np

__all__ = ["ACC_MEAN_FEATURES", "MAX_GRAVITY_DIRECTIONS", "feature_gravity", "span_gravity", "window_gravity"]

#: At most this many training gravity directions are kept (a random subset).
MAX_GRAVITY_DIRECTIONS = 400


def window_gravity(acc, starts, length: int) -> np.ndarray:
    """Unit vector of the mean acceleration of every window (phone frame), shape (k, 3).

    Windows whose mean is (nearly) zero (free fall) have no direction: NaN rows.
    """
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    return span_gravity(acc, starts, starts + int(length))


#: The phone-frame features that are the window means of the acceleration along x, y, z (``all52``, ``all52+gyro``).
ACC_MEAN_FEATURES = ("acc_x__mean", "acc_y__mean", "acc_z__mean")


def feature_gravity(X, feature_names) -> np.ndarray | None:
    """:func:`window_gravity` read off a phone-frame feature matrix of the windows, or None when it cannot be.

    The window gravity is the unit mean of the window's acceleration, and the
    ``all52`` / ``all52+gyro`` features of a window in the **phone frame** hold that mean
    (:data:`ACC_MEAN_FEATURES`, the window's own samples summed): normalising those three
    columns gives the same direction without a second pass over the recording. The two
    differ by rounding only (:func:`span_gravity` takes differences of running sums,
    which lose about 1e-13 relative on a 10-minute recording). Windows whose mean is
    (nearly) zero have no direction (NaN rows), as in :func:`span_gravity`.

    Parameters
    ----------
    X : (k, p) features of the windows in the phone frame, columns ``feature_names``.
    feature_names : the column names.

    Returns
    -------
    (k, 3) unit vectors, or None when a mean column is missing (e.g. ``paper34``) or a
    mean is not finite: the caller then uses :func:`window_gravity`.
    """
    names = list(feature_names)
    if not all(n in names for n in ACC_MEAN_FEATURES):
        return None
    mean = np.asarray(X, dtype=float)[:, [names.index(n) for n in ACC_MEAN_FEATURES]]
    if not np.isfinite(mean).all():
        return None
    norm = np.linalg.norm(mean, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = mean / norm[:, None]
    out[~(norm > 1e-6)] = np.nan
    return out


def span_gravity(acc, starts, ends) -> np.ndarray:
    """:func:`window_gravity` of windows of different lengths (``[start, end)`` spans, e.g. step windows)."""
    acc = np.asarray(acc, dtype=float)
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    ends = np.asarray(ends, dtype=np.int64).reshape(-1)
    cum = np.zeros((len(acc) + 1, 3))
    np.cumsum(acc, axis=0, out=cum[1:])
    length = np.maximum(ends - starts, 1).astype(float)
    mean = (cum[ends] - cum[starts]) / length[:, None]
    norm = np.linalg.norm(mean, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = mean / norm[:, None]
    out[~(norm > 1e-6)] = np.nan
    return out


def _nearest_angle(g: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """Angle (rad) from each row of ``g`` to the nearest of ``dirs``; NaN rows give NaN."""
    if len(dirs) == 0:
        return np.full(len(g), np.nan)
    if not len(g):
        return np.zeros(0)
    bad = ~np.isfinite(g).all(axis=1)
    any_bad = bad.any()
    cos = ((np.where(bad[:, None], 0.0, g) if any_bad else g) @ dirs.T).max(axis=1)
    out = np.arccos(np.clip(cos, -1.0, 1.0))
    if any_bad:
        out[bad] = np.nan
    return out


def _subsample_dirs(g: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    g = g[np.all(np.isfinite(g), axis=1)]
    if len(g) > MAX_GRAVITY_DIRECTIONS:
        g = g[np.sort(rng.choice(len(g), MAX_GRAVITY_DIRECTIONS, replace=False))]
    return g
