"""The :class:`Recording` container: one uniformly sampled IMU recording.

A recording holds the accelerometer (m/s^2, gravity included), an optional
gyroscope (rad/s), an optional per-sample label, metadata and any ground-truth
events the source format carries (``reference``). It is validated when it is
built, so every algorithm downstream may assume finite values, matching shapes
and SI units. The checks live beside it: :mod:`gaitml.recording.units` (unit
judgement and conversion), :mod:`gaitml.recording.ranges` (values no sensor can
produce), :mod:`gaitml.recording.timestamps` (times, rate, gaps) and
:mod:`gaitml.recording.resampling` (onto a uniform grid).

Irregularly timed samples (phones log "as fast as possible") are turned into a
uniform recording by :meth:`Recording.from_timestamps`, an explicit, documented
resampling step whose original rate, jitter and gaps are reported in ``meta``
(nothing is silently dropped or filled). A gap too long to bridge
(:func:`~gaitml.recording.timestamps.max_bridge_s`) is refused with its position
and length, or cut into segments on request (:meth:`Recording.segments_from_timestamps`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitml.errors import InputError
from gaitml.recording.ranges import as_2d3, check_finite, check_ranges
from gaitml.recording.resampling import decimation_factor, resample_uniform
from gaitml.recording.timestamps import check_rate, check_timed_samples, judge_timestamps, split_points
from gaitml.recording.units import check_units, convert_units, note_conversions

__all__ = ["Recording"]


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
        acc = as_2d3("acc", self.acc)
        if len(acc) == 0:
            raise InputError("the recording has no samples; check the file is not empty.")
        check_finite("acc", acc)
        fs = float(self.sampling_rate_hz)
        check_rate(fs)
        gyr = None
        if self.gyr is not None:
            gyr = as_2d3("gyr", self.gyr)
            if len(gyr) != len(acc):
                raise InputError(f"`gyr` has {len(gyr)} samples but `acc` has {len(acc)}; they must match.")
            check_finite("gyr", gyr)
        meta = dict(self.meta)
        labels = None
        if self.labels is not None:
            labels = np.asarray(self.labels).astype(str)
            if labels.shape != (len(acc),):
                raise InputError(f"`labels` must have shape ({len(acc)},), got {labels.shape}.")
        if self.check_units:
            warning = check_units(acc, gyr, meta)
            if warning and warning not in meta.get("warnings", []):
                meta["warnings"] = [*meta.get("warnings", []), warning]
        check_ranges(acc, gyr, dict(self.meta))
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
        acc = as_2d3("acc", acc)
        gyr_arr = None if gyr is None else as_2d3("gyr", gyr)
        acc, gyr_arr = convert_units(acc, gyr_arr, acc_unit, gyr_unit)
        meta = dict(meta or {})
        note_conversions(meta, acc_unit, gyr is not None and gyr_unit == "deg/s")
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
        anti_alias: bool = True,
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
        ``sampling_rate_hz`` to resample to is given. The rate is judged over
        the whole file (:func:`~gaitml.recording.timestamps.judge_timestamps`:
        quantised timestamps, rate changes with their position, reported in
        ``meta`` and ``meta['warnings']``); down-sampling filters before it
        decimates (:mod:`gaitml.recording.resampling`) unless ``anti_alias=False``
        (for data already low-passed by the caller).

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
        t, acc, gyr_arr = check_timed_samples(t_s, acc, gyr)
        acc, gyr_arr = convert_units(acc, gyr_arr, acc_unit, gyr_unit)
        meta = dict(meta or {})
        note_conversions(meta, acc_unit, gyr is not None and gyr_unit == "deg/s")
        plan = judge_timestamps(t, sampling_rate_hz=sampling_rate_hz, max_gap_s=max_gap_s, uniform_tolerance=uniform_tolerance)
        # unit and range checks before resampling: interpolating a 1e308 would overflow
        if len(acc):
            check_units(acc, gyr_arr, meta)
            check_ranges(acc, gyr_arr, meta)
        meta.update(plan["meta"])
        fs = plan["fs"]
        finish_resampling_meta(meta, plan, anti_alias=anti_alias)
        if not plan["resampled"]:
            new_acc, new_gyr, new_labels = acc, gyr_arr, labels
        else:
            new_acc, new_gyr, new_labels = resample_uniform(
                t, acc, fs, gyr=gyr_arr, labels=labels, max_rate_hz=plan["max_rate_hz"] if anti_alias else None
            )
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
        t, acc_arr, gyr_arr = check_timed_samples(t_s, acc, gyr)
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


def finish_resampling_meta(meta: dict, plan: Mapping[str, Any], *, anti_alias: bool = True) -> None:
    """``meta['resampled']``, ``resample_method`` and the plan's warnings, as a file read whole or in blocks reports them."""
    meta["resampled"] = bool(plan["resampled"])
    if plan["resampled"]:
        k = decimation_factor(plan["max_rate_hz"], plan["fs"]) if anti_alias else 1
        meta["resample_method"] = "linear interpolation"
        if k > 1:
            meta["resample_method"] = f"linear interpolation at {k} x the rate, anti-alias FIR low-pass, every {k}-th sample kept"
    for w in plan["warnings"]:
        if w not in meta.get("warnings", []):
            meta["warnings"] = [*meta.get("warnings", []), w]
