"""Vectorised extraction of the 52 time-domain features of paper 003 sec. 3.2.

All windows are processed at once: the windows are strided views
(``numpy.lib.stride_tricks.sliding_window_view``) gathered into an array of
shape (n_windows, 4 channels, length) per block of windows, and every statistic
is a numpy reduction along the last axis (one sort per block serves min, max,
quartiles and mode). There is no per-window Python loop.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.features._catalogue import (
    FEATURE_SETS,
    MODE_BIN_WIDTH,
    feature_names,
    resolve_subset,
    uses_forward,
    uses_forward_face,
    uses_gyro,
)
from gaitml.features._forward import check_forward_window, forward_vectors
from gaitml.features._frame import check_frame, gravity_frame_rotations, rotate_windows
from gaitml.features._windows import WINDOW_LENGTH_S, WINDOW_OVERLAP, make_windows

__all__ = ["extract_features", "features_from_arrays", "magnitude_offset", "MAGNITUDE_OFFSET_MS2", "SMOOTHING_SAMPLES"]

#: g subtracted from |acc| (paper 003 eq. 1: g = 9.8 m/s^2).
MAGNITUDE_OFFSET_MS2 = 9.8
#: Moving-average length for the magnitude (paper 003 sec. 2.1: N = 3; the gather in
#: ``_window_block`` is written for this value, it is not a free parameter).
SMOOTHING_SAMPLES = 3
#: A window with std <= DEGENERATE_REL * (1 + |mean|) counts as constant.
DEGENERATE_REL = 1e-10
#: Windows per block (bounds the temporary memory to a few MB).
BLOCK_WINDOWS = 512
#: Up to this many windows are gathered by fancy indexing instead of strided views.
_FEW_WINDOWS = 16

_N_STATS = 52
_PAPER34_IDX = np.array([i for i, name in enumerate(FEATURE_SETS["all52"]) if name in set(FEATURE_SETS["paper34"])])


def magnitude_offset(sensor: str) -> float:
    """Offset subtracted from the magnitude: g for acc, 0 for gyr."""
    return MAGNITUDE_OFFSET_MS2 if sensor == "acc" else 0.0


def _raw_magnitude(xyz: np.ndarray, offset: float) -> np.ndarray:
    return np.sqrt(np.einsum("ij,ij->i", xyz, xyz)) - offset


def _window_block(xyz: np.ndarray, mag: np.ndarray, mag3: np.ndarray, starts: np.ndarray, length: int) -> np.ndarray:
    """Gather (k, 4, length): x, y, z and the per-window smoothed magnitude.

    ``mag3[j]`` is the 3-sample centred mean around sample ``j + 1`` of the whole
    signal; inside a window it equals the window's own centred moving average
    except at the first and last sample, where the average shrinks to 2 samples.
    """
    k = len(starts)
    out = np.empty((k, 4, length))
    if k > _FEW_WINDOWS:
        view = np.lib.stride_tricks.sliding_window_view(xyz, length, axis=0)  # (n-L+1, 3, L), no copy
        out[:, :3, :] = view[starts]
        if length > 2:
            out[:, 3, 1:-1] = np.lib.stride_tricks.sliding_window_view(mag3, length - 2)[starts]
    else:  # a few windows (streaming): one fancy-index gather has less call overhead
        idx = starts[:, None] + np.arange(length)
        out[:, :3, :] = xyz[idx].transpose(0, 2, 1)
        if length > 2:
            out[:, 3, 1:-1] = mag3[idx[:, :-2]]
    out[:, 3, 0] = (mag[starts] + mag[starts + 1]) / 2.0
    out[:, 3, -1] = (mag[starts + length - 2] + mag[starts + length - 1]) / 2.0
    return out


def _mode_sorted(sorted_vals: np.ndarray, width: float) -> np.ndarray:
    """Mode of binned values along the last axis of an already sorted array.

    Bins are ``floor(v / width + 1/2)`` (monotone, so the binned rows stay
    sorted); the longest run of equal bins wins, the first (smallest) on ties.
    """
    shape = sorted_vals.shape
    n = shape[-1]
    q = np.floor(sorted_vals.reshape(-1, n) / width + 0.5)
    pos = np.arange(n)
    run_start = np.zeros(q.shape, dtype=np.intp)
    np.multiply(q[:, 1:] != q[:, :-1], pos[1:], out=run_start[:, 1:])
    np.maximum.accumulate(run_start, axis=1, out=run_start)
    np.subtract(pos, run_start, out=run_start)  # run length - 1 at each position
    best = np.argmax(run_start, axis=1)  # first end of a longest run -> smallest value on ties
    return (q[np.arange(q.shape[0]), best] * width).reshape(shape[:-1])


def _quantile_sorted(sorted_vals: np.ndarray, p: float) -> np.ndarray:
    """Linear interpolation between order statistics (numpy's default, type 7)."""
    n = sorted_vals.shape[-1]
    h = p * (n - 1)
    lo = int(np.floor(h))
    hi = min(lo + 1, n - 1)
    frac = h - lo
    a = sorted_vals[..., lo]
    b = sorted_vals[..., hi]
    return a + (b - a) * frac


_SUM = np.add.reduce
_PAIR_A = np.array([0, 0, 1])
_PAIR_B = np.array([1, 2, 2])


def _rowdot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """sum(a * b) along the last axis without a temporary (einsum)."""
    return np.einsum("...k,...k->...", a, b)


def _stats52(w: np.ndarray, mode_width: float) -> np.ndarray:
    """The 52 statistics of a block (k, 4, L) -> (k, 52), paper order."""
    k, _, n = w.shape
    inv_n = 1.0 / n
    out = np.empty((k, _N_STATS))
    mean = _SUM(w, axis=-1) * inv_n  # (k, 4)
    d = w - mean[..., None]
    d2 = d * d
    m2 = _SUM(d2, axis=-1) * inv_n
    m3 = _rowdot(d2, d) * inv_n
    m4 = _rowdot(d2, d2) * inv_n
    s = np.sort(w, axis=-1)
    q1 = _quantile_sorted(s, 0.25)
    q3 = _quantile_sorted(s, 0.75)
    degenerate = np.sqrt(m2) <= DEGENERATE_REL * (1.0 + np.abs(mean))
    safe_m2 = np.where(degenerate, 1.0, m2)
    cov = np.stack([_rowdot(d[:, a], d[:, b]) for a, b in ((0, 1), (0, 2), (1, 2))], axis=1) * inv_n  # xy, xz, yz
    bad = degenerate[:, _PAIR_A] | degenerate[:, _PAIR_B]
    den = np.sqrt(safe_m2[:, _PAIR_A] * safe_m2[:, _PAIR_B])
    out[:, 0:4] = mean
    out[:, 4:8] = _SUM(np.abs(w), axis=-1) * inv_n
    out[:, 8:12] = m2
    out[:, 12:16] = _mode_sorted(s, mode_width)
    out[:, 16:20] = s[..., -1]
    out[:, 20:24] = s[..., 0]
    out[:, 24:28] = q3 - q1
    out[:, 28:32] = q3
    out[:, 32:35] = np.where(bad, 0.0, np.minimum(np.maximum(cov / den, -1.0), 1.0))
    out[:, 35:39] = np.where(degenerate, 0.0, m3 / safe_m2**1.5)
    out[:, 39:43] = np.where(degenerate, 0.0, m4 / (safe_m2 * safe_m2) - 3.0)
    np.abs(d, out=d)
    out[:, 43:47] = _SUM(d, axis=-1) * inv_n
    dd = w[..., 1:] - w[..., :-1]
    ddd = dd[..., 1:] - dd[..., :-1]
    out[:, 47:51] = _rowdot(ddd, ddd) * inv_n
    out[:, 51] = _rowdot(dd[:, 0], dd[:, 0]) * inv_n
    return out


def _sensor_stats(xyz: np.ndarray, sensor: str, starts: np.ndarray, length: int, rotations: np.ndarray | None = None) -> np.ndarray:
    """The 52 statistics of every window; ``rotations`` (k, 3, 3) turn x, y, z into a window's own frame."""
    mag = _raw_magnitude(xyz, magnitude_offset(sensor))
    mag3 = (mag[:-2] + mag[1:-1] + mag[2:]) / 3.0 if len(mag) >= 3 else np.zeros(0)
    width = MODE_BIN_WIDTH[sensor]
    out = np.empty((len(starts), _N_STATS))
    for b in range(0, len(starts), BLOCK_WINDOWS):  # blocks of windows, not windows
        st = starts[b : b + BLOCK_WINDOWS]
        block = _window_block(xyz, mag, mag3, st, length)
        if rotations is not None:  # the gravity frame (gaitml.features._frame); the magnitude is unchanged
            block[:, :3, :] = rotate_windows(block[:, :3, :], rotations[b : b + len(st)])
        out[b : b + len(st)] = _stats52(block, width)
    if rotations is not None and sensor == "acc":
        # gravity frame: x and y are horizontal and z is along the window mean, so the means of x
        # and y are zero, and x and y are principal axes of the horizontal covariance, so their
        # correlation is zero, by construction; set them exactly (rounding noise of ~1e-15 would
        # otherwise become a random feature once a classifier standardises it)
        out[:, 0:2] = 0.0
        out[:, 32] = 0.0  # acc_xy__corr
    return out


def _as_xyz(name: str, x) -> np.ndarray:
    arr = np.ascontiguousarray(x, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"`{name}` must have shape (n, 3), got {arr.shape}; pass x, y, z columns.")
    return arr


def features_from_arrays(acc, gyr=None, fs=None, starts=None, length=None, subset: str = "all52", frame: str = "phone") -> np.ndarray:
    """Feature matrix of the windows ``[start, start + length)`` of raw arrays.

    Parameters
    ----------
    acc : array, shape (n, 3)
        Acceleration in m/s^2, gravity included.
    gyr : array, shape (n, 3), optional
        Angular rate in rad/s; required by subsets ``'all52+gyro'`` and ``'all52+gyro+fwd'``.
    fs : float, optional
        Sampling rate in Hz. The 52 statistics are per sample (M4 and f(1) are
        sums of sample differences, as in paper 003 eqs. 8-9) and do not depend
        on it; the forward-vector group (``+fwd`` subsets) needs it for its band.
    starts : array of int, shape (k,)
        Window start indices (any order, may repeat).
    length : int
        Window length in samples (>= 2).
    subset : str
        ``'all52'``, ``'paper34'``, ``'all52+gyro'`` (alias ``'all'``), or the opt-in
        ``'all52+fwd'`` / ``'all52+gyro+fwd'``, which append the forward vector W1..W3
        (:mod:`gaitml.features._forward`), and ``'all52+fwdface'`` / ``'all52+gyro+fwdface'``
        (the same vector weighted by how face up the phone is, W4..W6).
    frame : {'phone', 'gravity'}
        Axes of the x, y, z statistics: the phone's own (paper 003), or each
        window's gravity-aligned frame (x right, y forward, z up; see
        :mod:`gaitml.features._frame`), which makes every feature independent of a
        constant rotation of the phone. The gyroscope is rotated with the same matrix.

    Returns
    -------
    ndarray, shape (k, n_features)
        Columns in the order of :func:`gaitml.features.feature_names`.
    """
    key = resolve_subset(subset)
    check_frame(frame)
    acc = _as_xyz("acc", acc)
    if starts is None or length is None:
        raise InputError("`starts` and `length` are required; get them from gaitml.features.make_windows or gaitml.signal.window_params.")
    length = int(length)
    if length < 2:
        raise InputError(f"window `length` must be >= 2 samples, got {length}; use a longer window.")
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    n = len(acc)
    if len(starts) and (starts.min() < 0 or starts.max() + length > n):
        raise InputError(
            f"window starts must lie in [0, {n - length}] for {n} samples and length {length}, got {starts.min()}..{starts.max()}."
        )
    if n < length:
        raise InputError(f"the signal has {n} samples, fewer than one window of {length}; use a longer recording or a shorter window.")
    if uses_forward(key) and not (fs is not None and np.isfinite(float(fs)) and float(fs) > 0):
        raise InputError(f"feature subset {key!r} needs the sampling rate `fs` (Hz) for its forward vector's band; pass fs.")
    rotations = gravity_frame_rotations(acc, starts, length) if frame == "gravity" else None
    blocks = [_sensor_stats(acc, "acc", starts, length, rotations)]
    if uses_gyro(key):
        if gyr is None:
            raise InputError(
                f"feature subset {key!r} needs a gyroscope but none was given; use a recording with gyr_x, gyr_y, gyr_z or subset 'all52'."
            )
        gyr = _as_xyz("gyr", gyr)
        if len(gyr) != n:
            raise InputError(f"`gyr` has {len(gyr)} samples but `acc` has {n}; they must match.")
        blocks.append(_sensor_stats(gyr, "gyr", starts, length, rotations))
    if uses_forward(key):
        blocks.append(forward_vectors(acc, float(fs), starts, length, rotations, face_up=uses_forward_face(key)))
    full = np.concatenate(blocks, axis=1) if len(blocks) > 1 else blocks[0]
    if key == "paper34":
        return np.ascontiguousarray(full[:, _PAPER34_IDX])
    return full


def extract_features(
    recording,
    windows: pd.DataFrame | None = None,
    *,
    subset: str = "all52",
    length_s: float = WINDOW_LENGTH_S,
    overlap: float = WINDOW_OVERLAP,
    frame: str = "phone",
) -> pd.DataFrame:
    """Feature table of a recording: one row per window, columns ``<channel>__<stat>``.

    Parameters
    ----------
    recording : Recording
    windows : DataFrame, optional
        From :func:`make_windows` (columns ``start``, ``end``; all windows of
        one length). ``None`` makes them with ``length_s``/``overlap`` and keeps
        every window (``min_label_fraction=0``).
    subset : str
        ``'all52'`` (F1..F52), ``'paper34'`` (paper 003 Table 1) or
        ``'all52+gyro'`` (F1..F52 then G1..G52; needs a gyroscope). ``'all'`` is
        an alias of ``'all52'``. Opt-in: ``'all52+fwd'`` and ``'all52+gyro+fwd'``
        append the forward vector W1..W3 (:mod:`gaitml.features._forward`).
    frame : {'phone', 'gravity'}
        ``'phone'`` (default, paper 003): the phone's x, y, z. ``'gravity'``: each
        window in its own gravity-aligned frame (x right, y forward, z up), so the
        features do not change when the phone is held in another orientation; see
        :mod:`gaitml.features._frame` for the construction and its limits. Column
        names stay ``acc_x__...`` etc. in both frames.

    Returns
    -------
    DataFrame
        Index = ``windows.index``; columns in catalogue order (F numbers
        ascending). ``attrs`` carries the window settings of ``windows``, the
        ``subset`` and the ``frame``.

    Notes
    -----
    Paper 003 sec. 3.2; see :mod:`gaitml.features._catalogue` for the readings of
    ambiguous definitions (third quartile, mode binning, excess kurtosis,
    per-window smoothing of the magnitude).
    """
    key = resolve_subset(subset)
    check_frame(frame)
    names = feature_names(key)
    gyr = recording.require_gyr(f"feature subset {key!r}") if uses_gyro(key) else None
    if windows is None:
        windows = make_windows(recording, length_s, overlap, min_label_fraction=0.0)
    if not {"start", "end"} <= set(windows.columns):
        raise InputError(
            f"`windows` needs columns 'start' and 'end', got {list(windows.columns)}; build it with gaitml.features.make_windows."
        )
    starts = windows["start"].to_numpy(dtype=np.int64)
    lengths = windows["end"].to_numpy(dtype=np.int64) - starts
    if len(starts) == 0:
        return pd.DataFrame(np.zeros((0, len(names))), columns=names, index=windows.index)
    if (lengths != lengths[0]).any():
        raise InputError(
            f"all windows must have the same length, got {lengths.min()}..{lengths.max()} samples; build them with gaitml.features.make_windows."
        )
    if uses_forward(key):  # a window too short for the forward vector's band: refused, not a column of zeros
        check_forward_window(int(lengths[0]), recording.sampling_rate_hz)
    x = features_from_arrays(recording.acc, gyr, recording.sampling_rate_hz, starts, int(lengths[0]), key, frame)
    df = pd.DataFrame(x, columns=names, index=windows.index)
    df.attrs.update(dict(windows.attrs), subset=key, frame=frame)
    return df
