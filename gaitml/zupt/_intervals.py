"""Shared helpers of the zero-velocity detectors: input checks, centred window sums and run tables.

All of these are vectorised; the window sums are :func:`gaitml.signal.centered_window_sums` (cumulative sums, ``np.diff`` on the mask); nothing
loops over samples.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pandas as pd
import scipy.fft

from gaitml.consts import ZUPT_COLUMNS
from gaitml.errors import InputError
from gaitml.signal import centered_window_sums

__all__ = [
    "INTERVAL_RULES",
    "acc_gyr_window",
    "check_interval_rules",
    "centered_sums",
    "half_window_samples",
    "intervals_table",
    "intervals_to_mask",
    "local_stride_period",
    "mask_runs",
    "merge_short_gaps",
    "range_max",
    "remove_short_runs",
    "stride_scaled_stances",
]

#: Shortest and longest stride period (s) searched by :func:`local_stride_period`.
#: A stride (two steps) lasts ~0.45 s in a sprint (cadence ~4.4 steps/s) and up to
#: ~2.5 s in very slow walking (cadence ~0.8 steps/s; Bohannon & Andrews, Physiotherapy
#: 97(3), 2011, meta-analysis of gait speed; Novacheck, Gait & Posture 7, 1998).
STRIDE_RANGE_S = (0.4, 2.5)
#: Length and hop (s) of the blocks over which the stride period is estimated: the block
#: holds at least two of the longest strides searched.
STRIDE_BLOCK_S = 6.0
STRIDE_HOP_S = 2.0
#: A shorter lag's autocorrelation peak of at least this fraction of the highest peak is taken as the period.
OCTAVE_RATIO = 0.7
#: Smallest normalised autocorrelation at the stride lag for the block to count as periodic gait.
MIN_STRIDE_CORRELATION = 0.3


#: The interval rules a detector may apply after its per-sample decision.
INTERVAL_RULES = ("stride", "fixed", "none")


def check_interval_rules(value: str) -> str:
    """``value`` if it is one of :data:`INTERVAL_RULES`, else an InputError naming them."""
    if value not in INTERVAL_RULES:
        raise InputError(f"`interval_rules` must be one of {', '.join(map(repr, INTERVAL_RULES))}, got {value!r}.")
    return value


def half_window_samples(half_window_s: float, sampling_rate_hz: float, *, what: str = "half_window_s") -> int:
    """Half-window ``s`` in samples: ``round(half_window_s * sampling_rate_hz)``, at least 1.

    The window ``[i - s, i + s]`` then spans ``2 s + 1`` samples, about
    ``2 * half_window_s`` seconds at any rate.
    """
    if not np.isfinite(half_window_s) or half_window_s <= 0:
        raise InputError(f"`{what}` must be a positive number of seconds, got {half_window_s!r}.")
    return max(1, int(round(float(half_window_s) * float(sampling_rate_hz))))


def acc_gyr_window(acc_ms2: np.ndarray, gyr_rads: np.ndarray, half: int) -> tuple[np.ndarray, np.ndarray, int]:
    """The inputs of a windowed acc-and-gyro detector: both as float arrays of shape (n, 3), and ``s >= 1``.

    Raises
    ------
    InputError
        The shapes differ or are not (n, 3), or the half-window ``half`` (in
        samples, ``half_window_samples`` in the messages) is below 1.
    """
    a = np.asarray(acc_ms2, dtype=float)
    w = np.asarray(gyr_rads, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3 or w.shape != a.shape:
        raise InputError(f"acc and gyr must both have shape (n, 3), got {a.shape} and {w.shape}.")
    s = int(half)
    if s < 1:
        raise InputError(f"`half_window_samples` must be >= 1, got {half}.")
    return a, w, s


def centered_sums(x: np.ndarray, half: int) -> tuple[np.ndarray, np.ndarray]:
    """Sums of ``x`` over ``[i - half, i + half]`` along axis 0 and the window counts.

    :func:`gaitml.signal.centered_window_sums` with the odd window ``2 half + 1``
    (truncated at the edges).
    """
    h = int(half)
    if h < 0:
        raise InputError(f"`half` must be >= 0, got {half}.")
    return centered_window_sums(x, 2 * h + 1)


def mask_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Starts and (exclusive) ends of the runs of True in a boolean mask."""
    m = np.asarray(mask, dtype=bool)
    if m.ndim != 1:
        raise InputError(f"a zero-velocity mask must be 1-D, got shape {m.shape}.")
    d = np.diff(np.concatenate(([False], m, [False])).astype(np.int8))
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def intervals_to_mask(start: np.ndarray, end: np.ndarray, n_samples: int) -> np.ndarray:
    """Boolean mask of length ``n_samples`` that is True on every ``[start, end)``."""
    start = np.clip(np.asarray(start, dtype=np.int64), 0, n_samples)
    end = np.clip(np.asarray(end, dtype=np.int64), 0, n_samples)
    d = np.zeros(n_samples + 1, dtype=np.int64)
    np.add.at(d, start, 1)
    np.add.at(d, end, -1)
    return np.cumsum(d[:-1]) > 0


def remove_short_runs(mask: np.ndarray, min_samples: int) -> np.ndarray:
    """Set runs of True shorter than ``min_samples`` to False (returns a new mask)."""
    m = np.asarray(mask, dtype=bool)
    if min_samples <= 1:
        return m.copy()
    s, e = mask_runs(m)
    keep = (e - s) >= min_samples
    return intervals_to_mask(s[keep], e[keep], len(m))


def merge_short_gaps(mask: np.ndarray, max_gap_samples: int) -> np.ndarray:
    """Fill the runs of False of at most ``max_gap_samples`` that lie between two runs of True.

    Gaps at the recording's edges (before the first or after the last run of True)
    are left alone: they are not bounded by two zero-velocity runs. Returns a new mask.
    """
    m = np.asarray(mask, dtype=bool)
    if max_gap_samples <= 0:
        return m.copy()
    s, e = mask_runs(m)
    if len(s) < 2:
        return m.copy()
    gs, ge = e[:-1], s[1:]  # gaps between consecutive runs
    fill = (ge - gs) <= max_gap_samples
    return m | intervals_to_mask(gs[fill], ge[fill], len(m))


def local_stride_period(
    x: np.ndarray,
    sampling_rate_hz: float,
    *,
    range_s: tuple[float, float] = STRIDE_RANGE_S,
    block_s: float = STRIDE_BLOCK_S,
    hop_s: float = STRIDE_HOP_S,
    min_correlation: float = MIN_STRIDE_CORRELATION,
    at: np.ndarray | None = None,
) -> np.ndarray:
    """Per-sample local stride period (s) of a foot-mounted signal, NaN where there is no gait.

    The signal (the gyro or acceleration magnitude of a foot-mounted IMU repeats once
    per stride of that foot) is cut into blocks of ``block_s`` every ``hop_s``; in each
    block the normalised autocorrelation (mean removed, biased estimate, computed by
    FFT) is searched for its local maxima with a lag in ``range_s``; the period is the
    shortest lag whose peak reaches :data:`OCTAVE_RATIO` of the highest (so a multiple
    of the period is not taken for it). A block whose peak there is below
    ``min_correlation`` has no stride period (NaN). The block
    values are interpolated linearly between block centres; samples beyond the first
    or last valid block take its value. All NaN when no block is periodic.

    With ``at`` (sample positions) one block is centred on each position instead
    (shifted inside the recording at its ends) and its period returned, NaN where not
    periodic: the value at a position then depends only on the ``block_s`` of signal
    around it, not on where the recording starts (a chunked run gives the same).

    Parameters
    ----------
    x : ndarray, shape (n,)
    sampling_rate_hz : float
    range_s : (float, float)
        Shortest and longest stride period searched (s).
    block_s, hop_s : float
        Block length and hop (s).
    min_correlation : float
        Smallest autocorrelation peak of a periodic block.
    at : int ndarray, optional
        Positions (samples) at which to estimate the period with a centred block.

    Returns
    -------
    ndarray, shape (n,) (or ``at``'s shape), stride period in seconds or NaN.

    Notes
    -----
    Autocorrelation period estimation as in the step counters of paper 000 (its
    autocorrelation baseline); here on a foot, where one period is one stride.
    """
    v = np.asarray(x, dtype=float)
    if v.ndim != 1:
        raise InputError(f"`x` must be 1-D, got shape {v.shape}.")
    fs = float(sampling_rate_hz)
    lo_s, hi_s = float(range_s[0]), float(range_s[1])
    if not 0 < lo_s < hi_s:
        raise InputError(f"`range_s` must be (shortest, longest) with 0 < shortest < longest, got {range_s!r}.")
    n = len(v)
    out = np.full(n if at is None else len(np.atleast_1d(at)), np.nan)
    blk = int(round(block_s * fs))
    lo, hi = max(2, int(np.floor(lo_s * fs))), int(np.ceil(hi_s * fs))
    if n < 2 or hi + 2 >= blk:
        raise InputError(f"`block_s` ({block_s} s) must exceed the longest stride searched ({hi_s} s); lengthen the block.")
    if n < hi + 3 or len(out) == 0:
        return out
    blk = min(blk, n)
    if at is not None:
        starts = np.clip(np.asarray(at, dtype=np.int64).ravel() - blk // 2, 0, n - blk)
    else:
        hop = max(1, int(round(hop_s * fs)))
        starts = np.arange(0, max(1, n - blk + 1), hop)
        if starts[-1] + blk < n:
            starts = np.append(starts, n - blk)
    idx = starts[:, None] + np.arange(blk)[None, :]
    b = v[idx]
    b = b - b.mean(axis=1, keepdims=True)
    nfft = scipy.fft.next_fast_len(blk + hi + 2, real=True)  # no circular wrap up to lag hi + 1
    f = scipy.fft.rfft(b, nfft, axis=1)
    r = scipy.fft.irfft(f.real**2 + f.imag**2, nfft, axis=1)[:, : hi + 2]
    r0 = r[:, :1]
    r = np.divide(r, r0, out=np.zeros_like(r), where=r0 > 0)
    hi = min(hi, r.shape[1] - 2)
    lags = np.arange(lo, hi + 1)
    seg = r[:, lo : hi + 1]
    peak = (seg >= r[:, lo - 1 : hi]) & (seg >= r[:, lo + 1 : hi + 2])
    score = np.where(peak, seg, -np.inf)
    height = score.max(axis=1)
    # the shortest lag whose peak reaches OCTAVE_RATIO of the highest: the period, not a multiple of it
    first = np.argmax(score >= OCTAVE_RATIO * height[:, None], axis=1)
    lag = lags[first].astype(float)
    height = score[np.arange(len(starts)), first]
    valid = np.isfinite(height) & (height >= float(min_correlation))
    if at is not None:
        return np.where(valid, lag / fs, np.nan)
    if not valid.any():
        return out
    centres = starts + blk / 2.0
    return np.interp(np.arange(n), centres[valid], lag[valid] / fs)


def stride_scaled_stances(
    mask: np.ndarray,
    stride_s: np.ndarray | Callable[[], np.ndarray],
    sampling_rate_hz: float,
    *,
    merge_gap_samples: int,
    min_interval_samples: int,
    evidence: np.ndarray | None = None,
    max_gap_stride_fraction: float = 0.25,
    neighbourhood_stride_fraction: float = 0.5,
) -> np.ndarray:
    """Interval rules that follow the local stride period: merge short gaps, keep one stance per stride.

    1. A gap between two zero-velocity runs is filled when it is at most
       ``merge_gap_samples`` and at most ``max_gap_stride_fraction`` of the local
       stride period (a swing lasts ~40 % of a walking stride and 60-80 % of a
       running one, so a quarter of a stride cannot hold a swing).
    2. A run of at least ``min_interval_samples`` is kept. A shorter run is kept only
       where the gait is periodic (``stride_s`` finite) and it holds the most
       zero-velocity evidence of all runs that come within
       ``neighbourhood_stride_fraction`` of the local stride period of it (edge to edge):
       each stride of a foot holds exactly one stance, so the strongest run of that
       neighbourhood is the stance and a weaker one beside it is a dip of the swing.
       Where ``stride_s`` is NaN (no periodic gait), and for a run cut by the
       recording's first or last sample (its length is unknown), short runs are
       dropped, as with fixed rules.

    Parameters
    ----------
    mask : bool ndarray, shape (n,)
        Per-sample zero-velocity decision.
    stride_s : ndarray, shape (n,), or a callable ``f(positions) -> periods``
        Local stride period (s) or NaN (:func:`local_stride_period`). A callable is
        called only at the gaps and short runs that need the period (their centres).
    sampling_rate_hz : float
    merge_gap_samples, min_interval_samples : int
        Longest gap filled, shortest run kept unconditionally (samples). Both 0: the
        mask is returned unchanged (the per-sample rule).
    evidence : ndarray, shape (n,), optional
        Per-sample zero-velocity evidence (>= 0 on zero-velocity samples, e.g. the
        threshold minus the statistic); a run's evidence is its sum. Default: 1 per
        sample (the run's length).
    max_gap_stride_fraction, neighbourhood_stride_fraction : float

    Returns
    -------
    bool ndarray, shape (n,)
    """
    m = np.asarray(mask, dtype=bool)
    n = len(m)
    fs = float(sampling_rate_hz)

    def period_at(pos: np.ndarray) -> np.ndarray:
        pos = np.clip(np.asarray(pos, dtype=np.int64), 0, max(n - 1, 0))
        if callable(stride_s):
            return np.asarray(stride_s(pos), dtype=float)
        t = np.asarray(stride_s, dtype=float)
        if t.shape != m.shape:
            raise InputError(f"`stride_s` must have the mask's shape {m.shape}, got {t.shape}.")
        return t[pos]

    gap_max, shortest = int(merge_gap_samples), int(min_interval_samples)
    if gap_max <= 0 and shortest <= 1:
        return m.copy()
    s, e = mask_runs(m)
    # the shortest stride searched bounds a quarter stride from below: gaps up to that need no period
    floor_gap = int(np.floor(max_gap_stride_fraction * STRIDE_RANGE_S[0] * fs))
    if gap_max > 0 and len(s) > 1:
        gs, ge = e[:-1], s[1:]
        need = ((ge - gs) <= gap_max) & ((ge - gs) > floor_gap)
        tg = np.full(len(gs), np.nan)
        if need.any():
            tg[need] = period_at((gs[need] + ge[need]) // 2)
        limit = np.where(np.isfinite(tg), np.minimum(gap_max, np.floor(max_gap_stride_fraction * tg * fs)), gap_max)
        fill = (ge - gs) <= limit
        m = m | intervals_to_mask(gs[fill], ge[fill], n)
        s, e = mask_runs(m)
    if shortest <= 1 or len(s) == 0:
        return m
    if evidence is None:
        ev = (e - s).astype(float)
    else:
        w = np.asarray(evidence, dtype=float)
        if w.shape != m.shape:
            raise InputError(f"`evidence` must have the mask's shape {m.shape}, got {w.shape}.")
        c = np.concatenate(([0.0], np.cumsum(np.where(m, np.maximum(w, 0.0), 0.0))))
        ev = c[e] - c[s]
    short = (e - s) < shortest
    centre = (s + e) // 2
    tc = np.full(len(s), np.nan)
    if short.any():
        tc[short] = period_at(centre[short])
    keep = ~short
    cand = np.flatnonzero(short & np.isfinite(tc))
    if len(cand):
        reach = neighbourhood_stride_fraction * tc[cand] * fs
        lo = np.searchsorted(e, s[cand] - reach, side="right")
        hi = np.searchsorted(s, e[cand] + reach, side="left")
        inside = (s[cand] > 0) & (e[cand] < n)
        keep[cand] = inside & (ev[cand] >= range_max(ev, lo, hi))
    return intervals_to_mask(s[keep], e[keep], n)


def range_max(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """``max(values[lo[i]:hi[i]])`` for every i (each range non-empty), by a sparse table (vectorised)."""
    v = np.asarray(values, dtype=float)
    lo = np.asarray(lo, dtype=np.int64)
    hi = np.asarray(hi, dtype=np.int64)
    if len(lo) == 0:
        return np.zeros(0)
    if np.any(hi <= lo):
        raise InputError("range_max needs non-empty ranges (hi > lo).")
    levels = [v]
    width = 1
    while 2 * width <= len(v):
        prev = levels[-1]
        levels.append(np.maximum(prev[: len(prev) - width], prev[width:]))
        width *= 2
    k = np.floor(np.log2(hi - lo)).astype(np.int64)
    out = np.empty(len(lo))
    for level in np.unique(k):
        sel = k == level
        tab = levels[level]
        out[sel] = np.maximum(tab[lo[sel]], tab[hi[sel] - (1 << level)])
    return out


def intervals_table(mask: np.ndarray, sampling_rate_hz: float) -> pd.DataFrame:
    """The zero-velocity interval table of DESIGN sec. 2: ``start``, ``end`` (exclusive), times in s."""
    s, e = mask_runs(mask)
    fs = float(sampling_rate_hz)
    table = pd.DataFrame({"start": s.astype(np.int64), "end": e.astype(np.int64), "t_start_s": s / fs, "t_end_s": e / fs})
    assert tuple(table.columns) == ZUPT_COLUMNS
    table.attrs["sampling_rate_hz"] = fs
    return table


#: Block length (samples) of :func:`apply_blockwise`: small enough that a block's
#: intermediate arrays stay in the CPU cache (~1.5x faster than whole-array passes).
BLOCK_SAMPLES = 32768


def apply_blockwise(fn, arrays: tuple[np.ndarray, ...], half: int, *, block_samples: int = BLOCK_SAMPLES):
    """Apply a centred-window function block by block; identical to ``fn(*arrays)``.

    ``fn`` maps arrays of n samples (axis 0) to one array or a tuple of arrays of n
    samples whose value at i depends only on samples ``[i - half, i + half]``
    (windows truncated at the recording's edges). Each block is extended by
    ``half`` samples on both sides, so interior windows see exactly the samples
    they would see in a whole-array call and the recording's edges stay the edges.
    """
    n = len(arrays[0])
    if n <= 2 * block_samples:
        return fn(*arrays)
    parts: list = []
    for b0 in range(0, n, block_samples):
        b1 = min(n, b0 + block_samples)
        lo = max(0, b0 - half)
        hi = min(n, b1 + half)
        res = fn(*(a[lo:hi] for a in arrays))
        sl = slice(b0 - lo, b0 - lo + (b1 - b0))
        parts.append(tuple(r[sl] for r in res) if isinstance(res, tuple) else res[sl])
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(p) for p in zip(*parts, strict=True))
    return np.concatenate(parts)
