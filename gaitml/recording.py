"""The :class:`Recording` container: one uniformly sampled IMU recording.

A recording holds the accelerometer (m/s^2, gravity included), an optional
gyroscope (rad/s), an optional per-sample label, metadata and any ground-truth
events the source format carries (``reference``). It is validated when it is
built, so every algorithm downstream may assume finite values, matching shapes
and SI units.

Irregularly timed samples (phones log "as fast as possible") are turned into a
uniform recording by :meth:`Recording.from_timestamps`, an explicit, documented
linear-interpolation step whose original rate, jitter and gaps are reported in
``meta`` (nothing is silently dropped or filled).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitml.consts import DEG2RAD, GRAVITY_MS2
from gaitml.errors import InputError

__all__ = ["Recording", "check_acc_unit", "check_rate", "resample_uniform", "MIN_RATE_HZ", "MAX_RATE_HZ"]

#: A median |acc| between these bounds (m/s^2 read as-is) means the data is in g.
_G_UNIT_BAND = (0.5, 2.0)
#: A median |acc| above this cannot be m/s^2 with gravity (milli-g, raw counts...).
_MAX_MEDIAN_ACC_MS2 = 50.0
#: A 99th-percentile |gyr| above this (read as rad/s) means the data is in deg/s:
#: 20 rad/s is 1146 deg/s, above what a phone or even a running foot turns at
#: for 1 % of the time (the gaitmap foot sensors stay below 10 rad/s).
_DEG_S_SUSPECT_RADS = 20.0
#: A median |acc| below this cannot include gravity (all zeros, or gravity removed).
_MIN_MEDIAN_ACC_MS2 = 0.5
#: Plausible uniform sampling rates for gait (steps at up to ~4 Hz need >= 5 Hz).
MIN_RATE_HZ = 5.0
MAX_RATE_HZ = 10_000.0
#: A sampling interval more than this many times the median counts as a gap.
GAP_FACTOR = 3.0


def check_acc_unit(acc: np.ndarray, *, what: str = "acc") -> None:
    """Raise :class:`InputError` if ``acc`` looks like it is in g, not m/s^2.

    The test is the median magnitude: a recording with gravity included has a
    median |acc| near 9.8 m/s^2; one in g has a median near 1.
    """
    if len(acc) == 0:
        return
    med = float(np.median(np.linalg.norm(acc, axis=1)))
    if med < _MIN_MEDIAN_ACC_MS2:
        raise InputError(
            f"{what} has no gravity (median |acc| = {med:.3g} m/s^2): gaitml needs the raw accelerometer with gravity "
            "included, not linear acceleration or zeros; export the raw sensor."
        )
    if _G_UNIT_BAND[0] <= med <= _G_UNIT_BAND[1]:
        raise InputError(
            f"{what} looks like it is in g, not m/s^2 (median |acc| = {med:.2f}); "
            "pass acc_unit='g' (CLI: --acc-unit g) or convert to m/s^2."
        )
    if med > _MAX_MEDIAN_ACC_MS2:
        raise InputError(
            f"{what} is implausibly large for m/s^2 with gravity (median |acc| = {med:.4g}; milli-g would give ~1000); convert it to m/s^2."
        )


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


def _check_gyr_unit(gyr: np.ndarray) -> None:
    if len(gyr) == 0:
        return
    p99 = float(np.percentile(np.linalg.norm(gyr, axis=1), 99))
    if p99 > _DEG_S_SUSPECT_RADS:
        raise InputError(
            f"gyr looks like it is in deg/s, not rad/s (99th percentile |gyr| = {p99:.1f}); "
            "pass gyr_unit='deg/s' (CLI: --gyr-unit deg/s) or convert to rad/s."
        )


def _as_2d3(name: str, x: Any) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"`{name}` must have shape (n, 3), got {arr.shape}; pass x, y, z columns.")
    return arr


def _check_finite(name: str, arr: np.ndarray) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        rows = np.flatnonzero(bad.any(axis=-1) if arr.ndim > 1 else bad)
        raise InputError(
            f"`{name}` has {int(bad.sum())} NaN/inf values (first at sample {int(rows[0])}); remove or interpolate them before loading."
        )


def _convert_units(acc, gyr, acc_unit: str, gyr_unit: str):
    if acc_unit == "g":
        acc = acc * GRAVITY_MS2
    elif acc_unit != "m/s^2":
        raise InputError(f"acc_unit must be 'm/s^2' or 'g', got {acc_unit!r}.")
    if gyr is not None:
        if gyr_unit == "deg/s":
            gyr = gyr * DEG2RAD
        elif gyr_unit != "rad/s":
            raise InputError(f"gyr_unit must be 'rad/s' or 'deg/s', got {gyr_unit!r}.")
    return acc, gyr


def _note_conversions(meta: dict, acc_unit: str, gyr_from_degs: bool) -> None:
    """Record in ``meta['converted']`` which unit conversions were applied."""
    conv = [c for c, applied in (("acc from g", acc_unit == "g"), ("gyr from deg/s", gyr_from_degs)) if applied]
    if conv:
        meta["converted"] = conv


@dataclasses.dataclass(frozen=True, eq=False)
class Recording:
    """One uniformly sampled IMU recording in SI units.

    Parameters
    ----------
    acc : ndarray, shape (n, 3)
        Specific force in m/s^2 (gravity included), phone/sensor frame.
    sampling_rate_hz : float
        The uniform sampling rate.
    gyr : ndarray, shape (n, 3), optional
        Angular rate in rad/s.
    labels : ndarray of str, shape (n,), optional
        Per-sample label (motion mode or any class name).
    meta : mapping
        Free metadata: ``subject``, ``session``, ``source``, ``format``, ``device``,
        ``position``, and what resampling did (``original_rate_hz``, ``jitter_s``,
        ``gaps``...).
    reference : mapping
        Ground-truth events the source carries, e.g. ``steps_t_s`` (true step
        times, s from the first sample), ``strides`` (a DataFrame).
    check_units : bool
        If True (default), refuse acceleration that looks like g and angular rate
        that looks like deg/s, with a hint. Use the ``acc_unit`` / ``gyr_unit``
        arguments of :meth:`from_arrays` to convert instead.

    Raises
    ------
    InputError
        On wrong shapes, non-finite values, a non-positive rate, an empty
        recording or implausible units.
    """

    acc: np.ndarray
    sampling_rate_hz: float
    gyr: np.ndarray | None = None
    labels: np.ndarray | None = None
    meta: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    reference: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    check_units: bool = True

    def __post_init__(self) -> None:
        acc = _as_2d3("acc", self.acc)
        if len(acc) == 0:
            raise InputError("the recording has no samples; check the file is not empty.")
        _check_finite("acc", acc)
        fs = float(self.sampling_rate_hz)
        check_rate(fs)
        gyr = None
        if self.gyr is not None:
            gyr = _as_2d3("gyr", self.gyr)
            if len(gyr) != len(acc):
                raise InputError(f"`gyr` has {len(gyr)} samples but `acc` has {len(acc)}; they must match.")
            _check_finite("gyr", gyr)
        labels = None
        if self.labels is not None:
            labels = np.asarray(self.labels).astype(str)
            if labels.shape != (len(acc),):
                raise InputError(f"`labels` must have shape ({len(acc)},), got {labels.shape}.")
        if self.check_units:
            try:
                check_acc_unit(acc)
            except InputError as exc:
                if "acc from g" in dict(self.meta).get("converted", []):
                    raise InputError(
                        f"{exc} (the data was converted from g as asked: drop --acc-unit g / acc_unit='g' if it is in m/s^2)"
                    ) from exc
                raise
            if gyr is not None:
                _check_gyr_unit(gyr)
        acc.setflags(write=False)
        if gyr is not None:
            gyr.setflags(write=False)
        if labels is not None:
            labels.setflags(write=False)
        object.__setattr__(self, "acc", acc)
        object.__setattr__(self, "gyr", gyr)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "sampling_rate_hz", fs)
        object.__setattr__(self, "meta", dict(self.meta))
        object.__setattr__(self, "reference", dict(self.reference))

    # ------------------------------------------------------------------ views
    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(self.acc.shape[0])

    @property
    def duration_s(self) -> float:
        """Duration from the first to one interval past the last sample, in s."""
        return self.n_samples / self.sampling_rate_hz

    @property
    def t_s(self) -> np.ndarray:
        """Sample times in s from the first sample (``k / sampling_rate_hz``)."""
        return np.arange(self.n_samples) / self.sampling_rate_hz

    @property
    def has_gyr(self) -> bool:
        """Whether the recording has a gyroscope."""
        return self.gyr is not None

    @property
    def name(self) -> str:
        """A short identifier: ``meta['id']``, else ``meta['session']``, else 'recording'."""
        return str(self.meta.get("id") or self.meta.get("session") or "recording")

    def require_gyr(self, what: str, alternative: str | None = None) -> np.ndarray:
        """Return the gyroscope or raise an InputError naming ``what`` needs it (and ``alternative``, another fix)."""
        if self.gyr is None:
            other = f", or {alternative}" if alternative else ""
            raise InputError(f"{what} needs a gyroscope but the recording has none; use a recording with gyr_x, gyr_y, gyr_z{other}.")
        return self.gyr

    def require_samples(self, n_min: int, what: str) -> None:
        """Raise an InputError if the recording is shorter than ``n_min`` samples."""
        if self.n_samples < n_min:
            raise InputError(
                f"the recording is too short for {what}: {self.n_samples} samples "
                f"({self.duration_s:.2f} s) < {n_min} needed; use a longer recording."
            )

    def replace(self, **changes: Any) -> Recording:
        """Return a copy with some fields replaced (validated again)."""
        return dataclasses.replace(self, **changes)

    def slice(self, start: int, stop: int) -> Recording:
        """Return samples ``[start, stop)`` as a new recording (reference times shifted)."""
        start, stop, _ = slice(start, stop).indices(self.n_samples)
        t0 = start / self.sampling_rate_hz
        ref: dict[str, Any] = {}
        for key, val in self.reference.items():
            if key.endswith("_t_s"):
                v = np.asarray(val, dtype=float) - t0
                ref[key] = v[(v >= 0) & (v < (stop - start) / self.sampling_rate_hz)]
        return Recording(
            acc=self.acc[start:stop],
            gyr=None if self.gyr is None else self.gyr[start:stop],
            labels=None if self.labels is None else self.labels[start:stop],
            sampling_rate_hz=self.sampling_rate_hz,
            meta={**self.meta, "slice": [start, stop]},
            reference=ref,
            check_units=False,
        )

    # ----------------------------------------------------------- constructors
    @classmethod
    def from_arrays(
        cls,
        acc: Any,
        sampling_rate_hz: float,
        *,
        gyr: Any = None,
        labels: Any = None,
        meta: Mapping[str, Any] | None = None,
        reference: Mapping[str, Any] | None = None,
        acc_unit: str = "m/s^2",
        gyr_unit: str = "rad/s",
    ) -> Recording:
        """Build a recording from uniformly sampled arrays, converting units if asked.

        ``acc_unit='g'`` multiplies by standard gravity; ``gyr_unit='deg/s'``
        converts to rad/s. The conversion is recorded in ``meta['converted']``.
        """
        acc = _as_2d3("acc", acc)
        gyr_arr = None if gyr is None else _as_2d3("gyr", gyr)
        acc, gyr_arr = _convert_units(acc, gyr_arr, acc_unit, gyr_unit)
        meta = dict(meta or {})
        _note_conversions(meta, acc_unit, gyr is not None and gyr_unit == "deg/s")
        return cls(acc=acc, gyr=gyr_arr, labels=labels, sampling_rate_hz=sampling_rate_hz, meta=meta, reference=dict(reference or {}))

    @classmethod
    def from_timestamps(
        cls,
        t_s: Any,
        acc: Any,
        *,
        gyr: Any = None,
        labels: Any = None,
        sampling_rate_hz: float | None = None,
        meta: Mapping[str, Any] | None = None,
        reference: Mapping[str, Any] | None = None,
        acc_unit: str = "m/s^2",
        gyr_unit: str = "rad/s",
        uniform_tolerance: float = 1e-3,
    ) -> Recording:
        """Build a uniform recording from samples at (possibly irregular) times.

        Resampling is linear interpolation of every channel onto the grid
        ``t_s[0] + k / sampling_rate_hz`` for all k with grid time <= ``t_s[-1]``;
        labels take the value of the latest original sample at or before each
        grid time. If the timestamps are already uniform (every interval within
        ``uniform_tolerance`` relative of the median) and no rate is requested,
        the samples are kept as they are.

        Linear interpolation errs by at most ``max_interval^2 * max|x''| / 8``:
        for a 2 Hz gait component logged at ~200 Hz that is below 1e-3 of its
        amplitude; log at >= 100 Hz when resampling matters.

        ``meta`` gains ``original_rate_hz`` (1 / median interval), ``jitter_s``
        (standard deviation of the intervals), ``max_interval_s``, ``gaps``
        (intervals longer than ``GAP_FACTOR`` x the median: ``[[t_start_s,
        duration_s], ...]``, bridged by interpolation), ``resampled`` (bool),
        ``n_original_samples`` and ``t0_original_s`` (the first timestamp, which
        becomes t = 0). Reference event times (``*_t_s`` keys) must be on the
        same clock as ``t_s``; they are shifted to the new origin.

        Raises
        ------
        InputError
            Fewer than 2 samples, non-finite times, duplicate or decreasing
            timestamps (with the first offending index and a fix).
        """
        t = np.asarray(t_s, dtype=float)
        if t.ndim != 1:
            raise InputError(f"timestamps must be 1-D, got shape {t.shape}.")
        acc = _as_2d3("acc", acc)
        if len(acc) != len(t):
            raise InputError(f"{len(t)} timestamps but {len(acc)} acc samples; they must match.")
        if len(t) < 2:
            raise InputError(f"need at least 2 timestamped samples to find the sampling rate, got {len(t)}; use a longer recording.")
        _check_finite("t", t)
        _check_finite("acc", acc)
        gyr_arr = None if gyr is None else _as_2d3("gyr", gyr)
        if gyr_arr is not None:
            if len(gyr_arr) != len(t):
                raise InputError(f"{len(t)} timestamps but {len(gyr_arr)} gyr samples; they must match.")
            _check_finite("gyr", gyr_arr)
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
        acc, gyr_arr = _convert_units(acc, gyr_arr, acc_unit, gyr_unit)
        med = float(np.median(dt))
        original_rate = 1.0 / med
        check_rate(original_rate, what="the rate of the timestamps")
        if sampling_rate_hz is not None:
            check_rate(float(sampling_rate_hz), what="the requested sampling rate")
        gap_mask = dt > GAP_FACTOR * med
        gaps = [[round(float(t[i] - t[0]), 6), round(float(dt[i]), 6)] for i in np.flatnonzero(gap_mask)]
        uniform = bool(np.all(np.abs(dt - med) <= uniform_tolerance * med))
        meta = dict(meta or {})
        meta.update(
            original_rate_hz=round(original_rate, 6),
            jitter_s=float(np.std(dt)),
            max_interval_s=float(dt.max()),
            gaps=gaps,
            n_original_samples=int(len(t)),
            t0_original_s=float(t[0]),
        )
        if uniform and sampling_rate_hz is None:
            fs = (len(t) - 1) / (t[-1] - t[0])
            fs = float(np.round(fs, 6))
            meta["resampled"] = False
            new_acc, new_gyr, new_labels = acc, gyr_arr, labels
        else:
            fs = float(sampling_rate_hz if sampling_rate_hz is not None else np.round(original_rate, 6))
            new_acc, new_gyr, new_labels = resample_uniform(t, acc, fs, gyr=gyr_arr, labels=labels)
            meta["resampled"] = True
            meta["resample_method"] = "linear interpolation"
        ref: dict[str, Any] = {}
        for key, val in dict(reference or {}).items():
            if key.endswith("_t_s"):
                ref[key] = np.asarray(val, dtype=float) - t[0]
            else:
                ref[key] = val
        _note_conversions(meta, acc_unit, gyr is not None and gyr_unit == "deg/s")
        return cls(acc=new_acc, gyr=new_gyr, labels=new_labels, sampling_rate_hz=fs, meta=meta, reference=ref)


def resample_uniform(
    t_s: np.ndarray,
    acc: np.ndarray,
    sampling_rate_hz: float,
    *,
    gyr: np.ndarray | None = None,
    labels: Any = None,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Linearly interpolate samples at increasing times ``t_s`` onto a uniform grid.

    The grid is ``t_s[0] + k / sampling_rate_hz`` for every k whose time does
    not pass ``t_s[-1]``. Labels are carried by the latest original sample at or
    before each grid time (sample-and-hold: labels cannot be interpolated).

    Returns
    -------
    acc, gyr, labels : resampled arrays (gyr and labels None when not given).
    """
    t = np.asarray(t_s, dtype=float)
    n_new = int(np.floor((t[-1] - t[0]) * sampling_rate_hz + 1e-9)) + 1
    grid = t[0] + np.arange(n_new) / sampling_rate_hz

    def interp(x: np.ndarray) -> np.ndarray:
        return np.column_stack([np.interp(grid, t, x[:, j]) for j in range(x.shape[1])])

    new_acc = interp(acc)
    new_gyr = None if gyr is None else interp(gyr)
    new_labels = None
    if labels is not None:
        lab = np.asarray(labels).astype(str)
        idx = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 1)
        new_labels = lab[idx]
    return new_acc, new_gyr, new_labels
