"""Gyroscope bias from the still stretches of a recording.

A gyroscope at rest reads its bias (a constant offset per axis plus noise). Phone logs that
come uncalibrated (e.g. the raw iOS gyroscope) carry biases of the order of 0.01-0.1 rad/s,
which integrate into a heading drift of 30-340 deg/min and tip the integrated vertical
(the attitude of paper 003 sec. 4.2 integrates the rate as given). The classic remedy is to
average the rate while the device is known to be at rest ("zero angular rate update",
e.g. Foxlin 2005 for foot-mounted units; the static calibration recordings of the tyrex
benchmark, Michel et al. PerCom 2017, measure exactly this).

Rest is recognised per window of ``window_s`` seconds (half-overlapping) by three tests
that all must pass:

- the mean specific-force magnitude is within ``acc_magnitude_tol_ms2`` of g (not
  accelerating, not in free fall);
- the standard deviation of the specific-force magnitude is at most ``acc_std_max_ms2``
  (no steps, no handling);
- every gyroscope axis has a standard deviation of at most ``gyr_std_max_rads`` (no
  rotation; a constant bias does not raise the standard deviation, so a biased gyroscope
  is recognised at rest as well as a calibrated one);
- the mean rate is at most ``max_bias_rads`` on every axis (0.2 rad/s, 11 deg/s, above the
  biases of phone gyroscopes, of the order of 0.01-0.1 rad/s): a phone lying on a turntable
  or a swivel chair turning evenly is not at rest. A turn slower than that and perfectly
  even would still pass; the median over all still windows keeps it from dominating while
  the true rest is longer.

The bias is the median over the still windows of their mean rate, per axis (robust to a
window that slipped through while the phone turned slowly). It is used only when the still
windows cover at least ``min_still_s`` seconds together.

Fallback without a still stretch: the bias is **not** removed (zero), and the result says
so (``method='none'`` and a note). A bias estimated from a moving phone (e.g. the mean rate
over a walk) would mix the walker's turns into it; a walk round a loop turns by 360 deg per
lap, which is not a bias. So a recording that never rests is integrated as logged, and the
caller can pass a bias measured elsewhere (a static calibration recording) instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError

__all__ = [
    "GyroBias",
    "StillWindows",
    "estimate_gyro_bias",
    "gyro_bias_from_still",
    "gyro_bias_from_windows",
    "read_gyro_bias_json",
    "remove_gyro_bias",
    "steady_tilt_mask",
    "gyro_still_windows",
]

#: Defaults of the still detector (see the module docstring); ``gaitml pdr --gyro-bias`` and
#: :class:`gaitml.pdr.attitude.AttitudeEstimator` use them.
STILL_WINDOW_S = 1.0
STILL_ACC_MAGNITUDE_TOL_MS2 = 0.4
STILL_ACC_STD_MAX_MS2 = 0.15
STILL_GYR_STD_MAX_RADS = 0.03
STILL_MIN_S = 2.0
STILL_MAX_BIAS_RADS = 0.2
#: Still time a separate still recording (:func:`gyro_bias_from_still`) must hold, seconds. The static
#: bias test (IEEE Std 952-1997, annex C: the bias is the output averaged over a stretch at rest) needs
#: enough samples that the average's noise is far below the bias: phone gyroscopes at rest read with a
#: standard deviation of 0.001-0.003 rad/s per sample (the tyrex calibration logs, Michel et al. PerCom
#: 2017), so 5 s at 50-200 Hz average it down to under 2e-4 rad/s (0.7 deg/min of heading drift). The
#: shortest still gyroscope log of tyrex (``calib_gyr_iPhone5_d4``) holds 7.9 s.
STILL_RECORDING_MIN_S = 5.0
#: Defaults of :func:`steady_tilt_mask` (where an online bias estimate may learn from gravity).
STEADY_WINDOW_S = 1.0
STEADY_GYR_STD_MAX_RADS = 0.25
STEADY_ACC_MAGNITUDE_TOL_MS2 = 1.0


@dataclass
class GyroBias:
    """A gyroscope bias estimate and how it was obtained.

    Attributes
    ----------
    bias_rads : (3,) float, the bias per axis (rad/s) that is subtracted from the rate.
    method : ``'still'`` (from still stretches), ``'none'`` (no still stretch: nothing
        removed), ``'given'`` (passed by the caller), ``'still-recording'`` (from a separate
        recording of the phone lying still, :func:`gyro_bias_from_still`), ``'file'`` (read from a
        gaitml-written JSON, :func:`read_gyro_bias_json`) or ``'off'`` (turned off); a tracked
        start gets ``'+online'`` appended (:class:`gaitml.pdr.attitude.AttitudeEstimator`).
    still_s : seconds of the recording recognised as still (0 unless ``method='still'`` or ``'none'``).
    n_still_windows : number of still windows.
    note : one line for the output, saying what was removed and why.
    source : where a bias measured elsewhere came from (the still recording or JSON file), else ``''``.
    """

    bias_rads: np.ndarray
    method: str
    still_s: float = 0.0
    n_still_windows: int = 0
    note: str = ""
    params: dict = field(default_factory=dict)
    source: str = ""

    def to_dict(self) -> dict:
        """JSON-ready summary (``gaitml pdr --json``'s ``gyro_bias``)."""
        return {
            "method": self.method,
            "bias_rads": [float(v) for v in self.bias_rads],
            "bias_deg_per_s": [float(np.degrees(v)) for v in self.bias_rads],
            "still_s": float(self.still_s),
            "n_still_windows": int(self.n_still_windows),
            "note": self.note,
            **({"source": self.source} if self.source else {}),
            # a tracked bias: where the tracking started (the still stretches' or a still recording's bias)
            **({"start_bias_rads": [float(v) for v in self.params["start_bias_rads"]]} if "start_bias_rads" in self.params else {}),
        }


def _window_stats(x: np.ndarray, win: int, hop: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Start indices, means and standard deviations of half-overlapping windows of a (n, k) array (cumulative sums)."""
    n = len(x)
    starts = np.arange(0, n - win + 1, hop)
    c1 = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(x, axis=0)])
    c2 = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(x * x, axis=0)])
    s1 = c1[starts + win] - c1[starts]
    s2 = c2[starts + win] - c2[starts]
    mean = s1 / win
    var = np.maximum(s2 / win - mean * mean, 0.0)
    return starts, mean, np.sqrt(var)


@dataclass
class StillWindows:
    """The still test of every window of a recording (or of part of one), before the median.

    Attributes
    ----------
    start : (k,) int, the windows' first samples, counted from the start of the whole recording
        (windows start at multiples of the hop, half a window, so the windows of parts cut out of
        one recording are the whole recording's windows).
    still : (k,) bool, the windows that pass all tests of the module docstring.
    mean_rate_rads : (k, 3) each window's mean angular rate (rad/s).
    window : window length in samples.
    sampling_rate_hz : the sample rate.
    params : the still detector's settings.
    """

    start: np.ndarray
    still: np.ndarray
    mean_rate_rads: np.ndarray
    window: int
    sampling_rate_hz: float
    params: dict = field(default_factory=dict)

    def select(self, lo: int, hi: int) -> StillWindows:
        """The windows starting in samples ``[lo, hi)`` (e.g. a chunk's core)."""
        k = (self.start >= lo) & (self.start < hi)
        return StillWindows(self.start[k], self.still[k], self.mean_rate_rads[k], self.window, self.sampling_rate_hz, dict(self.params))


def gyro_still_windows(
    acc_ms2,
    gyr_rads,
    sampling_rate_hz: float,
    *,
    offset: int = 0,
    window_s: float = STILL_WINDOW_S,
    acc_magnitude_tol_ms2: float = STILL_ACC_MAGNITUDE_TOL_MS2,
    acc_std_max_ms2: float = STILL_ACC_STD_MAX_MS2,
    gyr_std_max_rads: float = STILL_GYR_STD_MAX_RADS,
    max_bias_rads: float = STILL_MAX_BIAS_RADS,
) -> StillWindows:
    """The still test of every half-overlapping window (module docstring), without the median.

    ``offset`` is the index of the first sample in the whole recording: the windows start at
    the whole recording's multiples of the hop, so the windows of the parts of a recording
    read in pieces (each piece holding a window beyond the part it stands for) are the windows
    of the recording read whole, and :func:`gyro_bias_from_windows` over all of them gives
    :func:`estimate_gyro_bias` of the whole recording. Other parameters as
    :func:`estimate_gyro_bias`.
    """
    acc = np.asarray(acc_ms2, dtype=float)
    gyr = np.asarray(gyr_rads, dtype=float)
    if acc.ndim != 2 or acc.shape[1] != 3 or gyr.shape != acc.shape:
        raise InputError(f"`acc_ms2` and `gyr_rads` must both have shape (n, 3), got {acc.shape} and {gyr.shape}.")
    if not np.isfinite(sampling_rate_hz) or sampling_rate_hz <= 0:
        raise InputError(f"`sampling_rate_hz` must be a positive number, got {sampling_rate_hz}.")
    params = {
        "window_s": window_s,
        "acc_magnitude_tol_ms2": acc_magnitude_tol_ms2,
        "acc_std_max_ms2": acc_std_max_ms2,
        "gyr_std_max_rads": gyr_std_max_rads,
        "max_bias_rads": max_bias_rads,
    }
    win = max(2, int(round(window_s * sampling_rate_hz)))
    hop = max(1, win // 2)
    first = (-int(offset)) % hop  # the first local sample on the whole recording's hop grid
    n = len(acc)
    if n - first < win:
        return StillWindows(np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool), np.zeros((0, 3)), win, float(sampling_rate_hz), params)
    mag = np.linalg.norm(acc, axis=1)[:, None]
    ok = np.isfinite(mag[:, 0]) & np.isfinite(gyr).all(axis=1)
    if not ok.all():  # windows touching a non-finite sample never count as still
        mag = np.where(ok[:, None], mag, 0.0)
        gyr = np.where(ok[:, None], gyr, 0.0)
    starts, m_mean, m_std = _window_stats(mag[first:], win, hop)
    _, g_mean, g_std = _window_stats(gyr[first:], win, hop)
    starts = starts + first
    n_bad = np.concatenate([[0], np.cumsum(~ok)])
    finite_win = (n_bad[starts + win] - n_bad[starts]) == 0
    still = (
        finite_win
        & (np.abs(m_mean[:, 0] - GRAVITY_MS2) <= acc_magnitude_tol_ms2)
        & (m_std[:, 0] <= acc_std_max_ms2)
        & (g_std.max(axis=1) <= gyr_std_max_rads)
        & (np.abs(g_mean).max(axis=1) <= max_bias_rads)
    )
    return StillWindows(starts.astype(np.int64) + int(offset), still, g_mean, win, float(sampling_rate_hz), params)


def gyro_bias_from_windows(windows: StillWindows | list[StillWindows], *, min_still_s: float = STILL_MIN_S) -> GyroBias:
    """The bias of :func:`estimate_gyro_bias` from the still test of the windows (:func:`gyro_still_windows`).

    ``windows`` may be a list of the windows of the parts of one recording (each window in one
    part only, e.g. :meth:`StillWindows.select` of each chunk's core): the median and the still
    time are those of the recording read whole.
    """
    parts = [windows] if isinstance(windows, StillWindows) else list(windows)
    if not parts:
        raise InputError("gyro_bias_from_windows needs the windows of at least one part of a recording.")
    win, fs = parts[0].window, parts[0].sampling_rate_hz
    params = {**parts[0].params, "min_still_s": min_still_s}
    start = np.concatenate([w.start for w in parts])
    still = np.concatenate([w.still for w in parts])
    rate = np.concatenate([w.mean_rate_rads for w in parts])
    none = GyroBias(
        np.zeros(3),
        "none",
        note=f"no still stretch of >= {min_still_s:g} s: gyroscope bias not removed",
        params=params,
    )
    if len(start) == 0:
        return none
    # seconds covered by the union of the still windows (each covers `win` samples from its start)
    s = np.sort(start[still])
    covered = int(np.minimum(np.diff(s), win).sum() + win) if len(s) else 0
    still_s = float(covered / fs)
    n_still = int(still.sum())
    none.still_s, none.n_still_windows = still_s, n_still
    if n_still == 0 or still_s < min_still_s:
        none.note = f"still for {still_s:.1f} s (< {min_still_s:g} s needed): gyroscope bias not removed"
        return none
    bias = np.median(rate[still], axis=0)
    b = np.degrees(bias)
    return GyroBias(
        bias,
        "still",
        still_s=still_s,
        n_still_windows=n_still,
        note=f"gyroscope bias ({b[0]:.2f}, {b[1]:.2f}, {b[2]:.2f}) deg/s removed, estimated over {still_s:.1f} s still",
        params=params,
    )


def estimate_gyro_bias(
    acc_ms2,
    gyr_rads,
    sampling_rate_hz: float,
    *,
    window_s: float = STILL_WINDOW_S,
    acc_magnitude_tol_ms2: float = STILL_ACC_MAGNITUDE_TOL_MS2,
    acc_std_max_ms2: float = STILL_ACC_STD_MAX_MS2,
    gyr_std_max_rads: float = STILL_GYR_STD_MAX_RADS,
    min_still_s: float = STILL_MIN_S,
    max_bias_rads: float = STILL_MAX_BIAS_RADS,
) -> GyroBias:
    """Gyroscope bias from the still stretches of a recording (module docstring).

    Parameters
    ----------
    acc_ms2 : (n, 3) specific force including gravity, m/s^2.
    gyr_rads : (n, 3) angular rate, rad/s.
    sampling_rate_hz : sample rate of both.
    window_s : length of the still-test windows (half-overlapping).
    acc_magnitude_tol_ms2 : largest | mean |acc| - g | of a still window.
    acc_std_max_ms2 : largest standard deviation of |acc| in a still window.
    gyr_std_max_rads : largest standard deviation of any gyroscope axis in a still window.
    min_still_s : still time needed for an estimate; with less, nothing is removed.
    max_bias_rads : largest mean rate (any axis) of a still window.

    Returns
    -------
    GyroBias (``method='still'`` or ``'none'``). The same as :func:`gyro_bias_from_windows` of
    :func:`gyro_still_windows`, which a recording read in parts uses.
    """
    windows = gyro_still_windows(
        acc_ms2,
        gyr_rads,
        sampling_rate_hz,
        window_s=window_s,
        acc_magnitude_tol_ms2=acc_magnitude_tol_ms2,
        acc_std_max_ms2=acc_std_max_ms2,
        gyr_std_max_rads=gyr_std_max_rads,
        max_bias_rads=max_bias_rads,
    )
    return gyro_bias_from_windows(windows, min_still_s=min_still_s)


def remove_gyro_bias(gyr_rads, bias: GyroBias | np.ndarray) -> np.ndarray:
    """The rate with the bias subtracted (a new array)."""
    b = bias.bias_rads if isinstance(bias, GyroBias) else np.asarray(bias, dtype=float).reshape(3)
    return np.asarray(gyr_rads, dtype=float) - b


def _centered_stats(x: np.ndarray, win: int) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample mean and standard deviation over a centred window of ``win`` samples (shortened at the ends)."""
    n = len(x)
    c1 = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(x, axis=0)])
    c2 = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(x * x, axis=0)])
    lo = np.clip(np.arange(n) - win // 2, 0, n)
    hi = np.clip(np.arange(n) - win // 2 + win, 0, n)
    cnt = (hi - lo)[:, None]
    mean = (c1[hi] - c1[lo]) / cnt
    var = np.maximum((c2[hi] - c2[lo]) / cnt - mean * mean, 0.0)
    return mean, np.sqrt(var)


def steady_tilt_mask(
    acc_ms2,
    gyr_rads,
    sampling_rate_hz: float,
    *,
    window_s: float = STEADY_WINDOW_S,
    gyr_std_max_rads: float = STEADY_GYR_STD_MAX_RADS,
    acc_magnitude_tol_ms2: float = STEADY_ACC_MAGNITUDE_TOL_MS2,
) -> np.ndarray:
    """Samples around which the phone's tilt is steady, so the low-passed accelerometer is the vertical.

    A sample is steady when, over the centred window of ``window_s``, every gyroscope axis
    varies by at most ``gyr_std_max_rads`` (standard deviation: a bias does not count) and the
    mean specific-force magnitude is within ``acc_magnitude_tol_ms2`` of g. A phone held in
    front while walking passes; a phone swinging in the hand or in a trouser pocket does not
    (its low-passed accelerometer is tipped by the centripetal and step accelerations, so a
    bias learnt from it there would be wrong). Used to gate the online bias estimate of
    :class:`gaitml.pdr.attitude.AttitudeEstimator`.

    Returns
    -------
    (n,) bool.
    """
    acc = np.asarray(acc_ms2, dtype=float)
    gyr = np.asarray(gyr_rads, dtype=float)
    if acc.ndim != 2 or acc.shape[1] != 3 or gyr.shape != acc.shape:
        raise InputError(f"`acc_ms2` and `gyr_rads` must both have shape (n, 3), got {acc.shape} and {gyr.shape}.")
    if len(acc) == 0:
        return np.zeros(0, dtype=bool)
    win = max(2, int(round(window_s * sampling_rate_hz)))
    mag = np.linalg.norm(acc, axis=1)[:, None]
    m_mean, _ = _centered_stats(mag, win)
    _, g_std = _centered_stats(gyr, win)
    ok = (g_std.max(axis=1) <= gyr_std_max_rads) & (np.abs(m_mean[:, 0] - GRAVITY_MS2) <= acc_magnitude_tol_ms2)
    return ok & np.isfinite(mag[:, 0]) & np.isfinite(gyr).all(axis=1)


def gyro_bias_from_still(
    recording,
    *,
    min_still_s: float = STILL_RECORDING_MIN_S,
    source: str | None = None,
    window_s: float = STILL_WINDOW_S,
    acc_magnitude_tol_ms2: float = STILL_ACC_MAGNITUDE_TOL_MS2,
    acc_std_max_ms2: float = STILL_ACC_STD_MAX_MS2,
    gyr_std_max_rads: float = STILL_GYR_STD_MAX_RADS,
    max_bias_rads: float = STILL_MAX_BIAS_RADS,
) -> GyroBias:
    """The gyroscope bias from a separate recording of the same phone lying still (a static bias test).

    The static bias of a rate gyroscope is its output averaged while it does not rotate (IEEE Std
    952-1997, annex C; the tyrex benchmark's ``calib_gyr_<phone>_d<N>`` logs, Michel et al. PerCom
    2017, are such recordings). The still stretches are found by the still test of
    :func:`estimate_gyro_bias` (module docstring: |acc| near g and steady, every gyroscope axis
    steady, mean rate under ``max_bias_rads``), so a recording that was picked up or put down at
    its ends still gives the bias of its resting part. The bias is the **mean** over the still
    windows of their mean rate, per axis: on a recording made to be still, the average of the
    standard test, whose noise falls with the still time (the walk's own estimate takes the median
    instead, to resist a slow turn that passes the test).

    Parameters
    ----------
    recording : :class:`gaitml.recording.Recording` with a gyroscope (rad/s) and accelerometer (m/s^2).
    min_still_s : still time needed (:data:`STILL_RECORDING_MIN_S`); with less, InputError.
    source : where the recording came from (default its ``name``), kept in the result.
    Other parameters: the still test of :func:`estimate_gyro_bias`.

    Returns
    -------
    GyroBias with ``method='still-recording'``, its still time and ``source``.

    Raises
    ------
    InputError (one line naming the problem and the fix): no gyroscope, or less than
    ``min_still_s`` seconds still.
    """
    name = source if source is not None else getattr(recording, "name", "") or "the still recording"
    gyr = getattr(recording, "gyr", None)
    if gyr is None:
        raise InputError(f"the still recording {name} has no gyroscope; give a recording of the same phone with its gyroscope logged.")
    gyr = _measured_gyr(recording, gyr)
    windows = gyro_still_windows(
        recording.acc,
        gyr,
        recording.sampling_rate_hz,
        window_s=window_s,
        acc_magnitude_tol_ms2=acc_magnitude_tol_ms2,
        acc_std_max_ms2=acc_std_max_ms2,
        gyr_std_max_rads=gyr_std_max_rads,
        max_bias_rads=max_bias_rads,
    )
    med = gyro_bias_from_windows(windows, min_still_s=min_still_s)
    duration = recording.n_samples / recording.sampling_rate_hz
    if med.method != "still":
        raise InputError(
            f"the still recording {name} is still for {med.still_s:.1f} s of {duration:.1f} s ({_not_still_reason(recording, windows, min_still_s)}"
        )
    bias = windows.mean_rate_rads[windows.still].mean(axis=0)
    b = np.degrees(bias)
    return GyroBias(
        bias,
        "still-recording",
        still_s=med.still_s,
        n_still_windows=med.n_still_windows,
        note=f"gyroscope bias ({b[0]:.2f}, {b[1]:.2f}, {b[2]:.2f}) deg/s from the still recording {name} ({med.still_s:.1f} s still)",
        params={**med.params, "min_still_s": min_still_s, "still_recording_s": float(duration)},
        source=str(name),
    )


def _measured_gyr(recording, gyr) -> np.ndarray:
    """The gyroscope with the samples a reader filled where it did not run set to NaN (a merge of two clocks
    holds its edge sample there, ``meta['clock_merge']['gyr_filled_s']``, :mod:`gaitml.io._merge`): a held value
    is constant, so it would pass the still test without being measured."""
    g = np.array(gyr, dtype=float)
    filled = (getattr(recording, "meta", {}).get("clock_merge") or {}).get("gyr_filled_s") or []
    if filled:
        t = np.asarray(recording.t_s, dtype=float)
        half = 0.5 / recording.sampling_rate_hz
        for a, b in filled:
            g[(t >= a - half) & (t <= b + half)] = np.nan
    return g


def _not_still_reason(recording, windows: StillWindows, min_still_s: float) -> str:
    """The end of :func:`gyro_bias_from_still`'s refusal: what the recording shows and the fix (a unit
    left unconverted shows as |acc| far from g or a rate far above any phone's bias)."""
    p = windows.params
    mag = float(np.nanmedian(np.linalg.norm(np.asarray(recording.acc, dtype=float), axis=1))) if recording.n_samples else float("nan")
    rate = float(np.nanmedian(np.abs(windows.mean_rate_rads).max(axis=1))) if len(windows.start) else 0.0
    if np.isfinite(mag) and abs(mag - GRAVITY_MS2) > 2.0:
        return f"its |acc| is {mag:.2f} m/s^2, not g = {GRAVITY_MS2:.2f}): check the accelerometer's unit (--acc-unit)."
    if rate > p["max_bias_rads"]:
        return (
            f"its mean rate is {rate:.2f} rad/s, above the {p['max_bias_rads']:g} rad/s of any phone's bias): check the gyroscope's "
            "unit (--gyr-unit) or that the phone was not turning."
        )
    return (
        f">= {min_still_s:g} s needed, with |acc| within {p['acc_magnitude_tol_ms2']:g} m/s^2 of g and every gyroscope axis steady "
        f"to {p['gyr_std_max_rads']:g} rad/s); record the phone lying untouched on a table for longer."
    )


def read_gyro_bias_json(path) -> GyroBias:
    """A gyroscope bias from a gaitml-written JSON: ``gaitml pdr --json``'s output (its ``gyro_bias``
    record) or that record alone (:meth:`GyroBias.to_dict`).

    Returns GyroBias with ``method='file'`` and ``source`` the path. Raises InputError (one line)
    when the file is not such a JSON, its bias is not 3 finite numbers, its ``method`` is not a string,
    its ``still_s`` not a finite number >= 0 or its ``n_still_windows`` not a whole number >= 0, or the
    record says no bias was measured (``method`` ``'none'`` or ``'off'``).
    """
    import json
    from pathlib import Path

    p = Path(path)
    try:
        obj = json.loads(p.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"cannot read a gyroscope bias from {p}: {exc}; give the JSON written by gaitml pdr --json.") from None
    rec = obj.get("gyro_bias", obj) if isinstance(obj, dict) else None
    if not isinstance(rec, dict) or "bias_rads" not in rec:
        raise InputError(
            f"{p} holds no gyroscope bias (no 'gyro_bias' record with 'bias_rads'); give the JSON written by gaitml pdr --json."
        )
    method = rec.get("method")
    if method is not None and not isinstance(method, str):
        raise InputError(
            f"{p}: the gyro_bias record's 'method' must be a string, got {method!r}; give the JSON written by gaitml pdr --json."
        )
    if method in ("none", "off"):
        raise InputError(
            f"{p} records no measured gyroscope bias (method {rec.get('method')!r}); write it from a run that found one "
            "(e.g. gaitml pdr STILL_RECORDING --json on a recording of the phone lying still)."
        )
    try:
        bias = np.asarray(rec["bias_rads"], dtype=float).reshape(-1)
    except (TypeError, ValueError):
        bias = np.zeros(0)
    if bias.shape != (3,) or not np.isfinite(bias).all():
        raise InputError(f"{p}: 'bias_rads' must be 3 finite numbers (rad/s), got {rec['bias_rads']!r}.")
    still_s, n_still = rec.get("still_s", 0.0) or 0.0, rec.get("n_still_windows", 0) or 0
    if isinstance(still_s, bool) or not isinstance(still_s, (int, float)) or not (math.isfinite(still_s) and still_s >= 0):
        raise InputError(
            f"{p}: the gyro_bias record's 'still_s' must be a finite number of seconds >= 0, got {still_s!r}; give the JSON written by gaitml pdr --json."
        )
    if (
        isinstance(n_still, bool)
        or not isinstance(n_still, (int, float))
        or not (math.isfinite(n_still) and n_still >= 0 and n_still == int(n_still))
    ):
        raise InputError(
            f"{p}: the gyro_bias record's 'n_still_windows' must be a whole number >= 0, got {n_still!r}; give the JSON written by gaitml pdr --json."
        )
    b = np.degrees(bias)
    return GyroBias(
        bias,
        "file",
        still_s=float(still_s),
        n_still_windows=int(n_still),
        note=f"gyroscope bias ({b[0]:.2f}, {b[1]:.2f}, {b[2]:.2f}) deg/s read from {p.name} (measured there as {method or '?'})",
        params={"file_method": method, **({"file_source": rec["source"]} if rec.get("source") else {})},
        source=str(p),
    )
