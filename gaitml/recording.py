"""The :class:`Recording` container: one uniformly sampled IMU recording.

A recording holds the accelerometer (m/s^2, gravity included), an optional
gyroscope (rad/s), an optional per-sample label, metadata and any ground-truth
events the source format carries (``reference``). It is validated when it is
built, so every algorithm downstream may assume finite values, matching shapes
and SI units.

Irregularly timed samples (phones log "as fast as possible") are turned into a
uniform recording by :meth:`Recording.from_timestamps`, an explicit, documented
linear-interpolation step whose original rate, jitter and gaps are reported in
``meta`` (nothing is silently dropped or filled). A gap too long to bridge
(:func:`max_bridge_s`: the longer of 1 s and ten sampling intervals) is refused
with its position and length, or cut into segments on request
(:meth:`Recording.segments_from_timestamps`).

Values no sensor can produce are refused naming the column and the limit
(:data:`gaitml.consts.ACC_LIMIT_MS2`, :data:`gaitml.consts.GYR_LIMIT_RADS`). Units
are judged on the whole distribution: acceleration in g or milli-g is refused;
a gyroscope in deg/s is refused when its median or 99th percentile is beyond any
human motion or gyro range in rad/s, and only warned about (``meta['warnings']``,
printed by the command line) when it is merely fast (:func:`check_gyr_unit`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitml.consts import ACC_LIMIT_MS2, DEG2RAD, GRAVITY_MS2, GYR_FULL_SCALE_MAX_RADS, GYR_LIMIT_RADS
from gaitml.errors import InputError

__all__ = [
    "Recording",
    "check_acc_unit",
    "check_gyr_unit",
    "check_range",
    "check_rate",
    "max_bridge_s",
    "resample_uniform",
    "split_points",
    "MIN_RATE_HZ",
    "MAX_RATE_HZ",
    "MAX_BRIDGE_S",
    "MAX_BRIDGE_FACTOR",
]

#: A median |acc| between these bounds (m/s^2 read as-is) means the data is in g.
_G_UNIT_BAND = (0.5, 2.0)
#: A median |acc| above this cannot be m/s^2 with gravity (milli-g, raw counts...).
_MAX_MEDIAN_ACC_MS2 = 50.0
#: Gyro unit guess (see :func:`check_gyr_unit`). A deg/s signal read as rad/s is
#: 57.3x too large everywhere: in its median, its rest level and its peaks.
#: A median |gyr| above this (860 deg/s) is no human motion in rad/s: it is deg/s
#: (the gaitmap foot sensors, which turn faster than a phone, have medians of
#: 0.7-5 rad/s; a thigh, and a phone in a trouser pocket, peaks near 10-20 rad/s
#: when sprinting, so its median stays well below 15).
_GYR_MEDIAN_DEG_S_RADS = 15.0
#: A 99th percentile |gyr| above this (1146 deg/s) is unusual for a phone; with
#: no rest level in the recording to tell the units apart, it is only warned about
#: (a phone in a pocket while jogging or sprinting reaches it in rad/s).
_GYR_P99_SUSPECT_RADS = 20.0
#: A 5th-percentile |gyr| below this is a rad/s rest level (gyro noise and residual
#: bias of a still phone, ~0.001-0.02 rad/s); the same rest in deg/s reads ~0.1-1.
_GYR_REST_RADS = 0.03
#: A median |acc| below this cannot include gravity (all zeros, or gravity removed).
_MIN_MEDIAN_ACC_MS2 = 0.5
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
#: Resampling never makes more than this many times the original samples (+1000):
#: up-sampling further adds no information and could exhaust memory.
_MAX_UPSAMPLE = 100.0


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


def check_range(name: str, arr: np.ndarray, limit: float, unit: str, alt: tuple[float, str] | None = None) -> None:
    """Raise InputError if any value of ``arr`` (columns x, y, z) is beyond ``limit`` in magnitude.

    Used with :data:`gaitml.consts.ACC_LIMIT_MS2` and :data:`gaitml.consts.GYR_LIMIT_RADS`:
    a value no sensor can output is a corrupt row or a wrong unit, and letting it
    through would overflow downstream sums (1e308). ``alt = (scale, fix)`` names a
    unit fix when the value times ``scale`` would be within the limit (e.g. deg/s).
    """
    if arr.size == 0:
        return
    with np.errstate(invalid="ignore"):
        bad = np.abs(arr) > limit
    if bad.any():
        i, j = (int(v) for v in np.argwhere(bad)[0])
        col = f"{name}_{'xyz'[j]}" if arr.ndim == 2 and arr.shape[1] == 3 else name
        v = float(arr[i, j])
        hint = f" ({alt[1]})" if alt is not None and abs(v) * alt[0] <= limit else ""
        raise InputError(
            f"{col} = {v:.4g} at sample {i} ({int(bad.sum())} value{'s' if int(bad.sum()) != 1 else ''} in all) is beyond any sensor's range "
            f"(|{name}| <= {limit:.4g} {unit}); remove or fix those rows{hint}."
        )


def check_acc_unit(acc: np.ndarray, *, what: str = "acc") -> None:
    """Raise :class:`InputError` if ``acc`` looks like it is in g, not m/s^2.

    The test is the median magnitude: a recording with gravity included has a
    median |acc| near 9.8 m/s^2; one in g has a median near 1.
    """
    if len(acc) == 0:
        return
    # clipped at the sensor limit so that a corrupt 1e308 cannot overflow the norm (check_range names it)
    med = float(np.median(np.sqrt(np.sum(np.square(np.clip(acc, -ACC_LIMIT_MS2, ACC_LIMIT_MS2)), axis=1))))
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


def check_gyr_unit(gyr: np.ndarray) -> str | None:
    """Judge whether a gyro read as rad/s is really in deg/s; refuse, warn or accept.

    The whole distribution of |gyr| is used, since a deg/s signal is 57.3x larger
    than the same motion in rad/s in every part of it:

    - refused (InputError) when the median |gyr| is above 15 rad/s (860 deg/s:
      no human motion turns that fast half of the time) or the 99th percentile is
      above the widest gyro full-scale range (4000 deg/s,
      :data:`gaitml.consts.GYR_FULL_SCALE_MAX_RADS`: no phone or wearable sensor
      can produce it in rad/s);
    - a warning text is returned when the 99th percentile is above 20 rad/s
      (1146 deg/s, fast for a phone but reached in a pocket while jogging) and the
      recording has no rad/s-sized rest level (5th percentile |gyr| < 0.03 rad/s)
      to confirm the unit;
    - None otherwise (accepted as rad/s).

    Returns
    -------
    str or None
        The warning (one line), or None.
    """
    if len(gyr) == 0:
        return None
    mag = np.sqrt(np.sum(np.square(np.clip(gyr, -GYR_LIMIT_RADS, GYR_LIMIT_RADS)), axis=1))
    p5, med, p99 = (float(v) for v in np.percentile(mag, [5, 50, 99]))
    fix = "pass gyr_unit='deg/s' (CLI: --gyr-unit deg/s) or convert to rad/s"
    if med > _GYR_MEDIAN_DEG_S_RADS or p99 > GYR_FULL_SCALE_MAX_RADS:
        raise InputError(
            f"gyr looks like it is in deg/s, not rad/s (median |gyr| = {med:.3g}, 99th percentile = {p99:.3g}: "
            f"as rad/s no human motion or gyro range gives that); {fix}."
        )
    if p99 > _GYR_P99_SUSPECT_RADS and p5 >= _GYR_REST_RADS:
        return (
            f"gyr may be in deg/s (99th percentile |gyr| = {p99:.3g} rad/s, median {med:.3g}, no rest level to tell); "
            f"accepted as rad/s: if it is deg/s, {fix}."
        )
    return None


def _check_units(acc: np.ndarray, gyr: np.ndarray | None, meta: Mapping[str, Any]) -> str | None:
    """The unit checks of acc (refuse) and gyr (refuse or a warning text, see :func:`check_gyr_unit`)."""
    try:
        check_acc_unit(acc)
    except InputError as exc:
        if "acc from g" in meta.get("converted", []):
            raise InputError(f"{exc} (the data was converted from g as asked: drop --acc-unit g / acc_unit='g' if it is in m/s^2)") from exc
        raise
    return None if gyr is None else check_gyr_unit(gyr)


def _check_ranges(acc: np.ndarray, gyr: np.ndarray | None, meta: Mapping[str, Any]) -> None:
    """Refuse values beyond any sensor's range (after unit conversion)."""
    conv = meta.get("converted", [])
    check_range(
        "acc",
        acc,
        ACC_LIMIT_MS2,
        "m/s^2",
        None if "acc from g" in conv else (GRAVITY_MS2 / 1000, "if the column is in milli-g, convert it"),
    )
    if gyr is not None:
        check_range(
            "gyr",
            gyr,
            GYR_LIMIT_RADS,
            "rad/s",
            None if "gyr from deg/s" in conv else (DEG2RAD, "if the column is in deg/s, pass --gyr-unit deg/s"),
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
        meta = dict(self.meta)
        labels = None
        if self.labels is not None:
            labels = np.asarray(self.labels).astype(str)
            if labels.shape != (len(acc),):
                raise InputError(f"`labels` must have shape ({len(acc)},), got {labels.shape}.")
        if self.check_units:
            warning = _check_units(acc, gyr, meta)
            if warning and warning not in meta.get("warnings", []):
                meta["warnings"] = [*meta.get("warnings", []), warning]
        _check_ranges(acc, gyr, dict(self.meta))
        acc.setflags(write=False)
        if gyr is not None:
            gyr.setflags(write=False)
        if labels is not None:
            labels.setflags(write=False)
        object.__setattr__(self, "acc", acc)
        object.__setattr__(self, "gyr", gyr)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "sampling_rate_hz", fs)
        object.__setattr__(self, "meta", meta)
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
        max_gap_s: float | None = None,
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

        Gaps (intervals longer than ``GAP_FACTOR`` x the median) are bridged by
        interpolation and reported, but only up to ``max_gap_s`` (default
        :func:`max_bridge_s` of the median interval: the longer of 1 s and ten
        intervals). A longer gap is refused with its position and length: cut the
        file there, or build one recording per segment with
        :meth:`segments_from_timestamps` (``gaitml.io.read_segments``).

        Timestamps faster than :data:`MAX_RATE_HZ` are accepted only when a
        ``sampling_rate_hz`` to resample to is given (linear interpolation at the
        new grid points, no anti-alias filter: stated in ``meta``).

        ``meta`` gains ``original_rate_hz`` (1 / median interval), ``jitter_s``
        (standard deviation of the intervals), ``max_interval_s``, ``gaps``
        (``[[t_start_s, duration_s], ...]``, bridged by interpolation),
        ``resampled`` (bool), ``n_original_samples`` and ``t0_original_s`` (the
        first timestamp, which becomes t = 0). Reference event times (``*_t_s``
        keys) must be on the same clock as ``t_s``; they are shifted to the new
        origin.

        Raises
        ------
        InputError
            Fewer than 2 samples, non-finite times, duplicate or decreasing
            timestamps (with the first offending index and a fix), a gap longer
            than ``max_gap_s``, values beyond any sensor's range.
        """
        t, acc, gyr_arr = _check_timed_samples(t_s, acc, gyr)
        acc, gyr_arr = _convert_units(acc, gyr_arr, acc_unit, gyr_unit)
        meta = dict(meta or {})
        _note_conversions(meta, acc_unit, gyr is not None and gyr_unit == "deg/s")
        dt = np.diff(t)
        med = float(np.median(dt))
        original_rate = 1.0 / med
        if sampling_rate_hz is not None:
            check_rate(float(sampling_rate_hz), what="the requested sampling rate")
            if original_rate < MIN_RATE_HZ * (1 - 1e-6):
                check_rate(original_rate, what="the rate of the timestamps")
        else:
            check_rate(original_rate, what="the rate of the timestamps")
        limit = max_bridge_s(med) if max_gap_s is None else float(max_gap_s)
        long_gaps = np.flatnonzero(dt > limit)
        if long_gaps.size:
            i = int(long_gaps[0])
            raise InputError(
                f"a {dt[i]:.6g} s gap in the timestamps after sample {i} (t = {t[i] - t[0]:.6g} s from the start; "
                f"{long_gaps.size} gaps longer than {limit:.3g} s in all) is too long to bridge by interpolation; "
                "cut the file at its gaps with `gaitml split FILE --out DIR` (in Python: gaitml.io.read_segments)."
            )
        # unit and range checks before resampling: interpolating a 1e308 would overflow
        if len(acc):
            _check_units(acc, gyr_arr, meta)
            _check_ranges(acc, gyr_arr, meta)
        gaps = [[round(float(t[i] - t[0]), 6), round(float(dt[i]), 6)] for i in np.flatnonzero(dt > GAP_FACTOR * med)]
        uniform = bool(np.all(np.abs(dt - med) <= uniform_tolerance * med))
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
            if original_rate > 2 * fs:
                meta["resample_method"] = "linear interpolation (down-sampling without an anti-alias filter)"
        ref: dict[str, Any] = {}
        for key, val in dict(reference or {}).items():
            if key.endswith("_t_s"):
                ref[key] = np.asarray(val, dtype=float) - t[0]
            else:
                ref[key] = val
        return cls(acc=new_acc, gyr=new_gyr, labels=new_labels, sampling_rate_hz=fs, meta=meta, reference=ref)

    @classmethod
    def segments_from_timestamps(
        cls,
        t_s: Any,
        acc: Any,
        *,
        gyr: Any = None,
        labels: Any = None,
        meta: Mapping[str, Any] | None = None,
        reference: Mapping[str, Any] | None = None,
        max_gap_s: float | None = None,
        min_samples: int = 2,
        **kwargs: Any,
    ) -> list[Recording]:
        """Cut timestamped samples at every gap too long to bridge; one recording per segment.

        The cut points are the intervals longer than ``max_gap_s`` (default
        :func:`max_bridge_s` of the median interval of the whole recording); each
        segment is built by :meth:`from_timestamps` (same keyword arguments).
        Every segment's ``meta['segment']`` gives its ``index``, the number of
        segments ``of``, its first and last original sample and its start and end
        in s from the first timestamp of the whole recording; reference event
        times are shifted to each segment and kept only inside it. Segments with
        fewer than ``min_samples`` samples are dropped and counted in
        ``meta['segments_dropped']`` of every kept segment.

        Raises
        ------
        InputError
            Bad timestamps (as :meth:`from_timestamps`), or no segment long enough.
        """
        t, acc_arr, gyr_arr = _check_timed_samples(t_s, acc, gyr)
        lab = None if labels is None else np.asarray(labels)
        cuts = split_points(t, max_gap_s)
        bounds = list(zip(np.concatenate([[0], cuts + 1]), np.concatenate([cuts + 1, [len(t)]]), strict=True))
        keep = [(a, b) for a, b in bounds if b - a >= max(2, min_samples)]
        if not keep:
            raise InputError(
                f"the recording has {len(bounds)} segments between long gaps and none has {max(2, min_samples)} samples; use a longer recording."
            )
        out = []
        for k, (a, b) in enumerate(keep):
            m = dict(meta or {})
            m["segment"] = {
                "index": k,
                "of": len(keep),
                "first_sample": int(a),
                "last_sample": int(b - 1),
                "t_start_s": float(t[a] - t[0]),
                "t_end_s": float(t[b - 1] - t[0]),
            }
            m["segments_dropped"] = len(bounds) - len(keep)
            for key in ("id", "session"):
                if key in m and len(keep) > 1:
                    m[key] = f"{m[key]}#{k}"
            ref: dict[str, Any] = {}
            for key, val in dict(reference or {}).items():
                if key.endswith("_t_s"):
                    v = np.asarray(val, dtype=float)
                    ref[key] = v[(v >= t[a]) & (v <= t[b - 1])]
                elif not (key.startswith("n_") or key in ("steps", "trajectory")):
                    ref[key] = val
            rec = cls.from_timestamps(
                t[a:b],
                acc_arr[a:b],
                gyr=None if gyr_arr is None else gyr_arr[a:b],
                labels=None if lab is None else lab[a:b],
                meta=m,
                reference=ref,
                max_gap_s=np.inf,
                **kwargs,
            )
            if "steps_t_s" in rec.reference:
                rec.reference["n_steps_true"] = int(len(rec.reference["steps_t_s"]))
            out.append(rec)
        return out


def _check_timed_samples(t_s: Any, acc: Any, gyr: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Shapes, finiteness and strictly increasing times of timestamped samples."""
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
    if not np.isfinite(dt).all():
        raise InputError("the timestamps span more than the float range; check the time column's unit.")
    return t, acc, gyr_arr


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
    n_float = np.floor((t[-1] - t[0]) * sampling_rate_hz + 1e-9) + 1
    if n_float > _MAX_UPSAMPLE * len(t) + 1000:
        raise InputError(
            f"resampling {len(t)} samples at {sampling_rate_hz:g} Hz would make {n_float:.4g} samples "
            f"(more than {_MAX_UPSAMPLE:g}x the original); ask for a lower --sampling-rate-hz."
        )
    n_new = int(n_float)
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
