"""The walker's path from a tracked phone's positions (motion capture or a dense reference path).

A phone carried in the hand or a pocket moves with the arm and the hip at the step and stride
rates; the walker's body does not. :func:`body_track` low-passes the phone's true horizontal
path so that it follows the walker: the truth the PDR's distance and step lengths are scored
and calibrated against (:mod:`gaitml.evaluation.trajectory`, :mod:`gaitml.pdr.calibrate`).
"""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError

__all__ = ["BODY_CUTOFF_HZ", "body_track", "uniform_track"]

#: Low-pass cutoff that turns the phone's motion-capture path into the walker's body path:
#: a stride lasts about 1 s, so 0.5 Hz removes the phone's own swing at the stride and step
#: rates (1-2 Hz) and keeps the turns of a 5 m room (a lap of ~15 m at 1 m/s: 0.07 Hz).
BODY_CUTOFF_HZ = 0.5


def uniform_track(t_s, xy, what: str) -> tuple[np.ndarray, np.ndarray, float]:
    """Times, positions with lost positions (NaN) filled linearly, and the track's rate (Hz).

    Raises
    ------
    InputError
        Not (n, 2) with one time each or n < 10; times not finite and increasing; a
        non-uniform rate; fewer than 10 finite positions. ``what`` names the track.
    """
    t = np.asarray(t_s, dtype=float).reshape(-1)
    a = np.asarray(xy, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2 or len(a) != len(t) or len(t) < 10:
        raise InputError(f"`{what}` must be (n, 2) positions with one time each and n >= 10, got {a.shape} and {t.shape}.")
    dt = np.diff(t)
    if not np.isfinite(t).all() or (dt <= 0).any():
        raise InputError(f"the times of `{what}` must be finite and increasing.")
    if np.max(np.abs(dt - np.median(dt))) > 0.1 * np.median(dt):
        raise InputError(f"`{what}` must be sampled at a uniform rate (a motion-capture track); resample it first.")
    ok = np.isfinite(a).all(axis=1)
    if ok.sum() < 10:
        raise InputError(f"`{what}` has fewer than 10 finite positions.")
    if not ok.all():
        a = np.column_stack([np.interp(t, t[ok], a[ok, j]) for j in range(2)])
    return t, a, 1.0 / float(np.median(dt))


def body_track(t_s, xy, *, cutoff_hz: float = BODY_CUTOFF_HZ) -> np.ndarray:
    """The walker's path: a phone's true positions low-passed (zero-phase Butterworth, order 2).

    Positions lost by the motion capture (NaN) are filled by linear interpolation
    first. In the swinging hand the phone's own path is 10-75 % longer than the
    body's (tyrex README); the low-passed path follows the walker.

    Returns
    -------
    ndarray, shape (n, 2)
    """
    from scipy.signal import butter, filtfilt

    t, a, fs = uniform_track(t_s, xy, "true_xy")
    if not 0 < cutoff_hz < 0.5 * fs:
        raise InputError(f"`cutoff_hz` must be between 0 and half the track's rate ({0.5 * fs:g} Hz), got {cutoff_hz!r}.")
    b, c = butter(2, cutoff_hz / (0.5 * fs))
    pad = min(len(t) - 1, 3 * int(fs / cutoff_hz))
    return filtfilt(b, c, a, axis=0, padlen=pad)
