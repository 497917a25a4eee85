"""Timestamps of a recording: increasing times, a plausible rate, gaps to bridge or cut.

:func:`check_timed_samples` checks shapes, finiteness and strictly increasing
times; :func:`check_rate` refuses a rate no gait recording has;
:func:`max_bridge_s` and :func:`split_points` say which intervals are gaps too
long to bridge by interpolation.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml.errors import InputError
from gaitml.recording.ranges import as_2d3, check_finite

__all__ = [
    "check_rate",
    "check_timed_samples",
    "max_bridge_s",
    "split_points",
    "MIN_RATE_HZ",
    "MAX_RATE_HZ",
    "GAP_FACTOR",
    "MAX_BRIDGE_S",
    "MAX_BRIDGE_FACTOR",
]

#: Plausible uniform sampling rates for gait (steps at up to ~4 Hz need >= 5 Hz).
MIN_RATE_HZ = 5.0
MAX_RATE_HZ = 10_000.0
#: A sampling interval more than this many times the median counts as a gap
#: (reported in ``meta['gaps']``).
GAP_FACTOR = 3.0
#: Gaps are bridged by linear interpolation only up to
#: ``max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR x median interval)`` (see :func:`max_bridge_s`).
#: 1 s is about one stride (two steps) at a normal cadence, so a bridged gap hides
#: at most one stride of made-up straight-line signal; the relative bound keeps
#: the ordinary jitter of a slow logger (5-20 Hz) from counting as a gap to refuse.
#: A longer gap is refused (or, on request, the recording is cut there): bridging
#: it would invent minutes of signal (and a 10^7 s gap would allocate gigabytes).
MAX_BRIDGE_S = 1.0
MAX_BRIDGE_FACTOR = 10.0


def max_bridge_s(median_interval_s: float) -> float:
    """The longest sampling interval (s) that resampling may bridge by interpolation.

    ``max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR * median_interval_s)``: one stride, or
    ten of the recording's own sampling intervals when those are longer.
    """
    return max(MAX_BRIDGE_S, MAX_BRIDGE_FACTOR * float(median_interval_s))


def split_points(t_s: np.ndarray, limit_s: float | None = None) -> np.ndarray:
    """Indices ``i`` where the interval ``t_s[i] -> t_s[i + 1]`` is longer than the bridge limit.

    ``limit_s`` defaults to :func:`max_bridge_s` of the median interval.
    """
    t = np.asarray(t_s, dtype=float)
    if len(t) < 2:
        return np.zeros(0, dtype=int)
    dt = np.diff(t)
    lim = max_bridge_s(float(np.median(dt))) if limit_s is None else float(limit_s)
    return np.flatnonzero(dt > lim)


def check_rate(fs: float, *, what: str = "the sampling rate") -> None:
    """Raise InputError unless ``fs`` is a plausible sampling rate (MIN_RATE_HZ..MAX_RATE_HZ)."""
    if not np.isfinite(fs) or fs <= 0:
        raise InputError(f"{what} must be a positive number of Hz, got {fs!r}.")
    if fs < MIN_RATE_HZ * (1 - 1e-6):
        raise InputError(
            f"{what} is {fs:.4g} Hz, too low for gait (>= {MIN_RATE_HZ:g} Hz needed); "
            "if the time column is in ms or ns, convert it to seconds."
        )
    if fs > MAX_RATE_HZ * (1 + 1e-6):
        raise InputError(
            f"{what} is {fs:.4g} Hz, above {MAX_RATE_HZ:g} Hz; if the time column is not in seconds convert it, "
            "or ask for a lower --sampling-rate-hz."
        )


def check_timed_samples(t_s: Any, acc: Any, gyr: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Shapes, finiteness and strictly increasing times of timestamped samples."""
    t = np.asarray(t_s, dtype=float)
    if t.ndim != 1:
        raise InputError(f"timestamps must be 1-D, got shape {t.shape}.")
    acc = as_2d3("acc", acc)
    if len(acc) != len(t):
        raise InputError(f"{len(t)} timestamps but {len(acc)} acc samples; they must match.")
    if len(t) < 2:
        raise InputError(f"need at least 2 timestamped samples to find the sampling rate, got {len(t)}; use a longer recording.")
    check_finite("t", t)
    check_finite("acc", acc)
    gyr_arr = None if gyr is None else as_2d3("gyr", gyr)
    if gyr_arr is not None:
        if len(gyr_arr) != len(t):
            raise InputError(f"{len(t)} timestamps but {len(gyr_arr)} gyr samples; they must match.")
        check_finite("gyr", gyr_arr)
    dt = np.diff(t)
    if (dt == 0).any():
        i = int(np.flatnonzero(dt == 0)[0]) + 1
        raise InputError(
            f"duplicate timestamp {t[i]:.9g} s at sample {i} ({int((dt == 0).sum())} in all); "
            "remove duplicated rows or give each sample its own time."
        )
    if (dt < 0).any():
        i = int(np.flatnonzero(dt < 0)[0]) + 1
        raise InputError(f"timestamps decrease at sample {i} ({t[i - 1]:.9g} -> {t[i]:.9g} s); sort the rows by time or fix the clock.")
    if not np.isfinite(dt).all():
        raise InputError("the timestamps span more than the float range; check the time column's unit.")
    return t, acc, gyr_arr
