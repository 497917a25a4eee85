"""Plain per-sample reference implementations of the zero-velocity detectors.

Straightforward loops over samples (one window at a time, as the papers and
OpenShoe's GLRT loop describe them). They exist to check the vectorised
detectors (tests: equal outputs on random data) and as the baseline of the
benchmark ratio (``benchmarks/zupt.py``). Not for production use: ~1000x slower.
"""

from __future__ import annotations

import numpy as np

from gaitml.consts import GRAVITY_MS2

__all__ = ["reference_pseudo_std", "reference_shoe", "reference_gyro_range", "reference_magnitude_std", "reference_magnitude"]


def _window(n: int, i: int, h: int) -> slice:
    return slice(max(0, i - h), min(n, i + h + 1))


def reference_pseudo_std(gyr_rads: np.ndarray, s: int) -> np.ndarray:
    """sigma'(i) = std of [0]*(m) + G(i) with m = len(G(i)) (paper 001 eqs. 6-7), one window at a time."""
    g = np.sqrt(np.sum(np.asarray(gyr_rads, dtype=float) ** 2, axis=1))
    n = len(g)
    out = np.empty(n)
    for i in range(n):
        win = g[_window(n, i, s)]
        padded = np.concatenate([np.zeros(len(win)), win])
        out[i] = padded.std()
    return out


def reference_shoe(acc: np.ndarray, gyr: np.ndarray, h: int, sigma_a: float, sigma_w: float, g: float = GRAVITY_MS2) -> np.ndarray:
    """SHOE statistic by its definition (Skog et al. 2010), one window at a time."""
    n = len(acc)
    out = np.empty(n)
    for i in range(n):
        sl = _window(n, i, h)
        a = acc[sl]
        w = gyr[sl]
        m = a.mean(axis=0)
        d = a - g * m / np.linalg.norm(m)
        out[i] = (np.sum(d * d) / sigma_a**2 + np.sum(w * w) / sigma_w**2) / len(a)
    return out


def reference_gyro_range(acc: np.ndarray, gyr: np.ndarray, s: int, gyr_range_rads: float, acc_max_ms2: float) -> np.ndarray:
    """Gyro-range detector (paper 001 baseline 1) per sample: max axis range of gyr < thr OR max |a| < thr over the window."""
    n = len(acc)
    am = np.sqrt(np.sum(acc * acc, axis=1))
    out = np.empty(n, dtype=bool)
    for i in range(n):
        sl = _window(n, i, s)
        w = gyr[sl]
        rng = (w.max(axis=0) - w.min(axis=0)).max()
        out[i] = rng < gyr_range_rads or am[sl].max() < acc_max_ms2
    return out


def reference_magnitude_std(acc, gyr, s, acc_min, acc_max, acc_std, gyr_max, gyr_std) -> np.ndarray:
    """Magnitude-std detector (paper 001 baseline 2) per sample: the four conditions, stds over the window."""
    n = len(acc)
    am = np.sqrt(np.sum(acc * acc, axis=1))
    wm = np.sqrt(np.sum(gyr * gyr, axis=1))
    out = np.empty(n, dtype=bool)
    for i in range(n):
        sl = _window(n, i, s)
        out[i] = acc_min < am[i] < acc_max and am[sl].std() < acc_std and wm[i] < gyr_max and wm[sl].std() < gyr_std
    return out


def reference_magnitude(acc, fs, t_min, t_max, min_run_fraction) -> np.ndarray:
    """Paper 004 as a state machine: C(k), then drop runs shorter than the fraction of fs."""
    am = np.sqrt(np.sum(acc * acc, axis=1))
    n = len(am)
    need = min_run_fraction * fs
    out = np.zeros(n, dtype=bool)
    run_start = None
    for k in range(n + 1):
        inside = k < n and t_min < am[k] < t_max
        if inside and run_start is None:
            run_start = k
        elif not inside and run_start is not None:
            if k - run_start >= need - 1e-9:
                out[run_start:k] = True
            run_start = None
    return out
