"""A plain per-window reference implementation of the 52 features (for the tests and ``benchmarks/features.py``).

Written independently of the vectorised extractor: a Python loop over windows,
each window handled by textbook numpy/scipy calls (``np.percentile``,
``scipy.stats.skew``/``kurtosis``, ``np.corrcoef``, ``np.unique``,
``gaitml.signal.moving_average``). It defines the same statistics (see
:mod:`gaitml.features._catalogue`) and is what the extractor is checked against
to 1e-9 and timed against in ``benchmarks/features.py``.
"""

from __future__ import annotations

import numpy as np
import scipy.stats

from gaitml.features._catalogue import MODE_BIN_WIDTH, feature_names, resolve_subset
from gaitml.signal import moving_average

__all__ = ["reference_features", "reference_window_stats"]

_G = 9.8  # paper 003 eq. (1)


def _is_constant(v: np.ndarray) -> bool:
    return float(np.std(v)) <= 1e-10 * (1.0 + abs(float(np.mean(v))))


def _mode(v: np.ndarray, width: float) -> float:
    bins = np.floor(v / width + 0.5)
    values, counts = np.unique(bins, return_counts=True)
    return float(values[np.argmax(counts)] * width)


def _skew_np(c: np.ndarray) -> float:
    d = c - np.mean(c)
    return float(np.mean(d**3) / np.mean(d**2) ** 1.5)


def _kurt_np(c: np.ndarray) -> float:
    d = c - np.mean(c)
    return float(np.mean(d**4) / np.mean(d**2) ** 2 - 3.0)


def reference_window_stats(
    x: np.ndarray, y: np.ndarray, z: np.ndarray, mag: np.ndarray, width: float, *, use_scipy: bool = True
) -> list[float]:
    """F1..F52 of one window from its four channels (mag already preprocessed).

    ``use_scipy=False`` computes skewness and kurtosis from numpy moments instead
    of ``scipy.stats`` (whose per-call overhead dominates the loop): the
    benchmark reports the ratio against both loops.
    """
    skew = (lambda c: float(scipy.stats.skew(c, bias=True))) if use_scipy else _skew_np
    kurt = (lambda c: float(scipy.stats.kurtosis(c, fisher=True, bias=True))) if use_scipy else _kurt_np
    chans = [x, y, z, mag]
    row: list[float] = []
    row += [float(np.mean(c)) for c in chans]
    row += [float(np.mean(np.abs(c))) for c in chans]
    row += [float(np.var(c)) for c in chans]
    row += [_mode(c, width) for c in chans]
    row += [float(np.max(c)) for c in chans]
    row += [float(np.min(c)) for c in chans]
    row += [float(np.percentile(c, 75) - np.percentile(c, 25)) for c in chans]
    row += [float(np.percentile(c, 75)) for c in chans]
    for a, b in ((x, y), (x, z), (y, z)):
        row.append(0.0 if _is_constant(a) or _is_constant(b) else float(np.corrcoef(a, b)[0, 1]))
    row += [0.0 if _is_constant(c) else skew(c) for c in chans]
    row += [0.0 if _is_constant(c) else kurt(c) for c in chans]
    row += [float(np.mean(np.abs(c - np.mean(c)))) for c in chans]
    n = len(x)
    for c in chans:
        second = (c[2:] - c[1:-1]) - (c[1:-1] - c[:-2])
        row.append(float(np.sum(second**2)) / n)
    row.append(float(np.sum((x[1:] - x[:-1]) ** 2)) / n)
    return row


def reference_features(acc, gyr=None, starts=(), length: int = 75, subset: str = "all52", *, use_scipy: bool = True) -> np.ndarray:
    """Feature matrix computed one window at a time (slow, obviously correct)."""
    key = resolve_subset(subset)
    acc = np.asarray(acc, dtype=float)
    rows = []
    for s in np.asarray(starts, dtype=int):
        w = acc[s : s + length]
        mag = moving_average(np.linalg.norm(w, axis=1) - _G, 3, mode="centered")
        row = reference_window_stats(w[:, 0], w[:, 1], w[:, 2], mag, MODE_BIN_WIDTH["acc"], use_scipy=use_scipy)
        if key == "all52+gyro":
            g = np.asarray(gyr, dtype=float)[s : s + length]
            gmag = moving_average(np.linalg.norm(g, axis=1), 3, mode="centered")
            row += reference_window_stats(g[:, 0], g[:, 1], g[:, 2], gmag, MODE_BIN_WIDTH["gyr"], use_scipy=use_scipy)
        rows.append(row)
    out = np.asarray(rows, dtype=float).reshape(len(rows), -1 if rows else (104 if key == "all52+gyro" else 52))
    if key == "paper34":
        full = feature_names("all52")
        keep = set(feature_names("paper34"))
        out = out[:, [i for i, name in enumerate(full) if name in keep]]
    return out
