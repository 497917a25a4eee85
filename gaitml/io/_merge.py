"""Put an accelerometer and a gyroscope logged on separate clocks onto one time base.

Phone apps log each sensor "as fast as possible" with its own timestamps
(phyphox tables, Sensor Logger files); the two streams start and stop at
slightly different times and their sample times never coincide. gaitml merges
them in one documented way:

1. keep only the *overlap* of the two streams (the later start to the earlier
   end), never extrapolate;
2. keep the accelerometer's own timestamps inside the overlap (the
   accelerometer is what every step detector uses) and linearly interpolate each
   gyroscope axis onto them;
3. report what was done in ``meta['clock_merge']`` (shown by ``gaitml info``).

:meth:`gaitml.recording.Recording.from_timestamps` then makes the result
uniform (and reports that resampling separately). Linear interpolation of a
2 Hz gait component sampled at >= 100 Hz errs by < 1e-3 of its amplitude (see
``from_timestamps``).

Two streams that overlap for less than half of the shorter one are refused as
unsynchronised clocks (for example one table in seconds and the other in
milliseconds, or tables from two different recordings).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml.errors import InputError

__all__ = ["merge_clocks", "MIN_OVERLAP_FRACTION", "check_times"]

#: Refuse two streams whose overlap is shorter than this fraction of the shorter stream.
MIN_OVERLAP_FRACTION = 0.5


def check_times(t: np.ndarray, what: str) -> None:
    """One-line InputError unless ``t`` is finite and strictly increasing with >= 2 samples."""
    if len(t) < 2:
        raise InputError(f"{what} has {len(t)} samples; record for longer with this sensor switched on.")
    if not np.isfinite(t).all():
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise InputError(f"{what} has a missing or non-numeric time at row {i + 1}; export the recording again.")
    dt = np.diff(t)
    if (dt <= 0).any():
        i = int(np.flatnonzero(dt <= 0)[0]) + 1
        kind = "repeats" if dt[i - 1] == 0 else "goes back"
        raise InputError(
            f"{what}: time {kind} at row {i + 1} ({t[i - 1]:.9g} -> {t[i]:.9g} s); sort the rows by time or remove duplicated rows."
        )


def merge_clocks(
    t_acc: np.ndarray,
    acc: np.ndarray,
    t_gyr: np.ndarray,
    gyr: np.ndarray,
    *,
    what: str = "the recording",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
    """Interpolate the gyroscope onto the accelerometer's times over their overlap.

    Parameters
    ----------
    t_acc, t_gyr : ndarray, shape (n,), (m,)
        Sample times in s on the *same* clock, strictly increasing.
    acc, gyr : ndarray, shape (n, 3), (m, 3)
        Accelerometer (any unit) and gyroscope (any unit) samples.
    what : str
        Names the export in error messages.

    Returns
    -------
    t, acc, gyr : ndarrays
        The accelerometer times inside the overlap, its samples there, and the
        gyroscope linearly interpolated at those times.
    info : dict
        For ``meta['clock_merge']``: ``method``, ``overlap_s`` (start, end on the
        input clock), ``acc_rate_hz``, ``gyr_rate_hz`` (median rates),
        ``dropped_acc_samples`` and ``dropped_gyr_samples`` (outside the overlap).

    Raises
    ------
    InputError
        No overlap, or an overlap shorter than :data:`MIN_OVERLAP_FRACTION` of
        the shorter stream (unsynchronised clocks); too few samples; times not
        increasing.
    """
    t_acc = np.asarray(t_acc, dtype=float)
    t_gyr = np.asarray(t_gyr, dtype=float)
    acc = np.asarray(acc, dtype=float)
    gyr = np.asarray(gyr, dtype=float)
    check_times(t_acc, f"the accelerometer table of {what}")
    check_times(t_gyr, f"the gyroscope table of {what}")
    a0, a1, g0, g1 = float(t_acc[0]), float(t_acc[-1]), float(t_gyr[0]), float(t_gyr[-1])
    lo, hi = max(a0, g0), min(a1, g1)
    if hi <= lo:
        raise InputError(
            f"the accelerometer ({a0:.3f} to {a1:.3f} s) and gyroscope ({g0:.3f} to {g1:.3f} s) clocks of {what} do not overlap; "
            "export both sensors from the same recording, or remove the gyroscope table to read the accelerometer alone."
        )
    shorter = min(a1 - a0, g1 - g0)
    if hi - lo < MIN_OVERLAP_FRACTION * shorter:
        raise InputError(
            f"the accelerometer ({a0:.3f} to {a1:.3f} s) and gyroscope ({g0:.3f} to {g1:.3f} s) of {what} overlap for only "
            f"{hi - lo:.3f} s of {shorter:.3f} s: unsynchronised clocks (other time units or another recording?); "
            "export both sensors from the same recording with the same time unit."
        )
    keep = (t_acc >= lo) & (t_acc <= hi)
    if keep.sum() < 2:
        raise InputError(f"the accelerometer of {what} has fewer than 2 samples where the gyroscope runs; record for longer.")
    t = t_acc[keep]
    gyr_on_acc = np.column_stack([np.interp(t, t_gyr, gyr[:, j]) for j in range(gyr.shape[1])])
    n_gyr_used = int(((t_gyr >= lo) & (t_gyr <= hi)).sum())
    info = {
        "method": "gyroscope linearly interpolated onto the accelerometer times, overlap only",
        "overlap_s": [round(lo, 6), round(hi, 6)],
        "acc_rate_hz": round(1.0 / float(np.median(np.diff(t_acc))), 3),
        "gyr_rate_hz": round(1.0 / float(np.median(np.diff(t_gyr))), 3),
        "dropped_acc_samples": int(len(t_acc) - keep.sum()),
        "dropped_gyr_samples": int(len(t_gyr) - n_gyr_used),
    }
    return t, acc[keep], gyr_on_acc, info
