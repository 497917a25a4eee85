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
import scipy.signal
import scipy.stats

from gaitml.features._catalogue import MODE_BIN_WIDTH, feature_names, resolve_subset
from gaitml.signal import moving_average

__all__ = ["reference_features", "reference_forward", "reference_window_stats"]

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


def reference_forward(w: np.ndarray, fs: float, band=(0.5, 3.0)) -> list[float]:
    """The forward vector W1..W3 of one window (N, 3) (gaitml.features._forward), written out sample by sample.

    scipy's linear detrend, the full complex DFT with a symmetric mask, a loop for the
    circular central difference and the sums.
    """
    n = len(w)
    g = w.mean(axis=0)
    up = g / np.linalg.norm(g) if np.linalg.norm(g) > 1e-6 else np.array([0.0, 0.0, 1.0])
    d = scipy.signal.detrend(w, axis=0, type="linear")
    freq = np.abs(np.fft.fftfreq(n, d=1.0 / fs))
    mask = (freq >= band[0]) & (freq <= band[1])
    bp = np.real(np.fft.ifft(np.fft.fft(d, axis=0) * mask[:, None], axis=0))
    v = bp @ up
    h = bp - np.outer(v, up)
    dv = np.array([(v[(t + 1) % n] - v[(t - 1) % n]) * fs / 2.0 for t in range(n)])
    f = sum(h[t] * dv[t] for t in range(n)) / n
    den = np.sqrt(np.mean(np.sum(h * h, axis=1)) * np.mean(dv * dv))
    return [float(c) for c in (f / den if den > 1e-12 else np.zeros(3))]


def reference_features(
    acc, gyr=None, starts=(), length: int = 75, subset: str = "all52", *, use_scipy: bool = True, fs: float = 50.0
) -> np.ndarray:
    """Feature matrix computed one window at a time (slow, obviously correct); ``fs``: the forward vector's rate."""
    key = resolve_subset(subset)
    acc = np.asarray(acc, dtype=float)
    rows = []
    for s in np.asarray(starts, dtype=int):
        w = acc[s : s + length]
        mag = moving_average(np.linalg.norm(w, axis=1) - _G, 3, mode="centered")
        row = reference_window_stats(w[:, 0], w[:, 1], w[:, 2], mag, MODE_BIN_WIDTH["acc"], use_scipy=use_scipy)
        if "gyro" in key.split("+"):
            g = np.asarray(gyr, dtype=float)[s : s + length]
            gmag = moving_average(np.linalg.norm(g, axis=1), 3, mode="centered")
            row += reference_window_stats(g[:, 0], g[:, 1], g[:, 2], gmag, MODE_BIN_WIDTH["gyr"], use_scipy=use_scipy)
        if "fwd" in key.split("+"):
            row += reference_forward(w, fs)
        if "fwdface" in key.split("+"):  # the same vector times how face up the phone is
            up_z = float(np.mean(w[:, 2]) / np.linalg.norm(np.mean(w, axis=0)))
            row += [c * max(up_z, 0.0) for c in reference_forward(w, fs)]
        rows.append(row)
    out = np.asarray(rows, dtype=float).reshape(len(rows), -1 if rows else len(feature_names(key)))
    if key == "paper34":
        full = feature_names("all52")
        keep = set(feature_names("paper34"))
        out = out[:, [i for i, name in enumerate(full) if name in keep]]
    return out
