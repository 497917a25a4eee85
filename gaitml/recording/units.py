"""Units of a recording's channels: judged on the whole distribution, converted on request.

A recording holds specific force in m/s^2 (gravity included) and angular rate in
rad/s. Acceleration in g or milli-g is refused (:func:`check_acc_unit`: the median
|acc|, and its 5th percentile where the median cannot tell, as on a foot-mounted
sensor of a runner); a
gyroscope in deg/s is refused when its median or 99th percentile is beyond any
human motion or gyro range in rad/s, and only warned about when it is merely fast
(:func:`check_gyr_unit`). :func:`convert_units` applies the conversions a user
asks for (``acc_unit='g'``, ``gyr_unit='deg/s'``) and :func:`note_conversions`
records them in ``meta['converted']``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitml.consts import ACC_LIMIT_MS2, DEG2RAD, GRAVITY_MS2, GYR_FULL_SCALE_MAX_RADS, GYR_LIMIT_RADS
from gaitml.errors import InputError

__all__ = [
    "check_acc_unit",
    "check_gyr_unit",
    "check_units",
    "check_unit_magnitudes",
    "acc_magnitude",
    "gyr_magnitude",
    "judge_acc_magnitude",
    "acc_mean_norm",
    "judge_gyr_magnitude",
    "convert_units",
    "note_conversions",
    "ACC_UNITS",
    "GYR_UNITS",
]

#: The accepted unit names of the two channels.
ACC_UNITS = ("m/s^2", "g")
GYR_UNITS = ("rad/s", "deg/s")

#: A median |acc| between these bounds (m/s^2 read as-is) means the data is in g.
_G_UNIT_BAND = (0.5, 2.0)
#: A median |acc| above this cannot be m/s^2 with gravity (milli-g, raw counts...) unless the 5th
#: percentile is (a foot-mounted sensor of a runner: see :func:`judge_acc_magnitude`).
_MAX_MEDIAN_ACC_MS2 = 50.0
#: The low percentile of |acc| that tells the unit where the median cannot (:func:`judge_acc_magnitude`).
_LOW_PERCENTILE = 5.0
#: A 5th percentile |acc| up to this (2 g in m/s^2) is m/s^2 with gravity whatever the median.
_MAX_LOW_ACC_MS2 = _G_UNIT_BAND[1] * GRAVITY_MS2
#: A median |acc| below this (0.8 g in m/s^2) with gravity in m/s^2 is no sensor carried by a person:
#: with a 5th percentile in the g band it is a fast-moving sensor in g.
_G_RUN_MAX_MEDIAN = 8.0
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
#: No gravity by the mean vector: the norm of the recording's mean acceleration vector below this share of
#: its median |acc|. With gravity the mean specific force over whole strides is gravity turned into the sensor
#: frame (0.9 and more of the median for a carried phone, at least half of it for a foot that pitches by +-60
#: deg); linear acceleration (gravity removed) averages to the sensor's bias, under 0.01 of its median.
_MAX_MEAN_SHARE = 0.03
#: ... together with a 5th percentile of |acc| below this share of the median: linear acceleration passes
#: through zero (0.3-0.4), while a phone turned through every attitude at rest (a six-position calibration,
#: whose mean vector also cancels) or tumbling keeps |acc| near its median (0.95-1.0).
_MAX_LOW_SHARE_NO_GRAVITY = 0.45


def check_acc_unit(acc: np.ndarray, *, what: str = "acc") -> None:
    """Raise :class:`InputError` if ``acc`` looks like it is in g, not m/s^2.

    The test is the median magnitude: a recording with gravity included has a
    median |acc| near 9.8 m/s^2; one in g has a median near 1.
    """
    if len(acc) == 0:
        return
    judge_acc_magnitude(acc_magnitude(acc), what=what, mean_norm=acc_mean_norm(acc))


def acc_mean_norm(acc: np.ndarray) -> float:
    """The norm of the mean acceleration vector over the recording (NaN rows ignored): gravity's share of it."""
    m = np.nanmean(np.clip(np.asarray(acc, dtype=float), -ACC_LIMIT_MS2, ACC_LIMIT_MS2), axis=0)
    return float(np.linalg.norm(m)) if np.all(np.isfinite(m)) else float("nan")


def acc_magnitude(acc: np.ndarray) -> np.ndarray:
    """Per-sample |acc| (float32: the unit tests are thresholds, not sums), clipped at the sensor limit so that
    a corrupt 1e308 cannot overflow (check_range names it)."""
    return np.sqrt(np.sum(np.square(np.clip(acc, -ACC_LIMIT_MS2, ACC_LIMIT_MS2)), axis=1)).astype(np.float32)


def gyr_magnitude(gyr: np.ndarray) -> np.ndarray:
    """Per-sample |gyr|, clipped at the sensor limit (float32, as :func:`acc_magnitude`)."""
    return np.sqrt(np.sum(np.square(np.clip(gyr, -GYR_LIMIT_RADS, GYR_LIMIT_RADS)), axis=1)).astype(np.float32)


def judge_acc_magnitude(mag: np.ndarray, *, what: str = "acc", mean_norm: float | None = None) -> None:
    """The test of :func:`check_acc_unit` on the per-sample magnitudes of the whole recording
    (a file read in blocks collects them block by block and is judged by this same code).

    The median |acc| of a carried phone is near 1 g (9.8 in m/s^2, 1 in g, 1000 in milli-g); a
    foot-mounted sensor of a runner reads 4-5 g in its median (impacts and swings), but its low
    tail stays near 1 g: a sensor on a person spends more than 5 % of the time at or below 1 g
    (at rest, in a foot flat, in the unloading of each step; a running phone in a pocket
    reads 0.3 g there), so the 5th percentile (:data:`_LOW_PERCENTILE`) tells the unit where the
    median cannot:

    - no gravity: a median |acc| below :data:`_MIN_MEDIAN_ACC_MS2`;
    - g: a median |acc| in :data:`_G_UNIT_BAND` (0.5-2), or below :data:`_G_RUN_MAX_MEDIAN`
      (a median no m/s^2 recording with gravity has) with a 5th percentile of at most the band's
      top (2): a runner's foot in g (median 3.5-5.2, 5th percentile 0.6-1);
    - milli-g or counts: a median |acc| above :data:`_MAX_MEDIAN_ACC_MS2` (50) whose 5th
      percentile is above :data:`_MAX_LOW_ACC_MS2` (2 g in m/s^2): a runner's foot in m/s^2
      reaches a median of 50 with a 5th percentile of 6-10, the same foot in milli-g 600-1000.
      The percentile is taken over the samples that are not (near) zero (|acc| >= 0.5): a logger's
      zero rows (before the sensor starts, dropped rows filled with 0) say nothing of the unit.

    ``mean_norm`` (:func:`acc_mean_norm`, optional): a mean acceleration vector near zero (below
    :data:`_MAX_MEAN_SHARE` of the median) with a low tail through zero (5th percentile below
    :data:`_MAX_LOW_SHARE_NO_GRAVITY` of the median) says the recording has no gravity at all
    (linear acceleration, in any unit: multiplied by 9.81 it would look right): refused as such,
    before any unit is judged.
    """
    if len(mag) == 0:
        return
    med = float(np.median(mag))
    if med < _MIN_MEDIAN_ACC_MS2:
        raise InputError(
            f"{what} has no gravity (median |acc| = {med:.3g} m/s^2): gaitml needs the raw accelerometer with gravity "
            "included, not linear acceleration or zeros; export the raw sensor."
        )
    if mean_norm is not None and mean_norm < _MAX_MEAN_SHARE * med:
        low_all = float(np.percentile(mag, _LOW_PERCENTILE))
        if low_all < _MAX_LOW_SHARE_NO_GRAVITY * med:
            raise InputError(
                f"{what} has no gravity (median |acc| = {med:.3g}, mean acceleration vector {mean_norm:.2g}: it averages "
                "to zero): gaitml needs the raw accelerometer with gravity included, not linear acceleration; export the raw sensor."
            )
    if _G_UNIT_BAND[0] <= med <= _G_UNIT_BAND[1]:
        raise InputError(
            f"{what} looks like it is in g, not m/s^2 (median |acc| = {med:.2f}); "
            "pass acc_unit='g' (CLI: --acc-unit g) or convert to m/s^2."
        )
    if med < _G_RUN_MAX_MEDIAN or med > _MAX_MEDIAN_ACC_MS2:
        live = mag[mag >= _MIN_MEDIAN_ACC_MS2]
        low = float(np.percentile(live, _LOW_PERCENTILE)) if len(live) else 0.0
        if med < _G_RUN_MAX_MEDIAN and low <= _G_UNIT_BAND[1]:
            raise InputError(
                f"{what} looks like it is in g, not m/s^2 (median |acc| = {med:.2f}, 5th percentile {low:.2f}: a fast-moving "
                "sensor, a runner's foot, in g; in m/s^2 it would have lost gravity); pass acc_unit='g' (CLI: --acc-unit g) or convert to m/s^2."
            )
        if med > _MAX_MEDIAN_ACC_MS2 and low > _MAX_LOW_ACC_MS2:
            raise InputError(
                f"{what} is implausibly large for m/s^2 with gravity (median |acc| = {med:.4g}, 5th percentile {low:.4g}; "
                "milli-g would give ~1000); convert it to m/s^2."
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
    return judge_gyr_magnitude(gyr_magnitude(gyr))


def judge_gyr_magnitude(mag: np.ndarray) -> str | None:
    """The judgement of :func:`check_gyr_unit` on the per-sample magnitudes of the whole recording."""
    if len(mag) == 0:
        return None
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


def check_units(acc: np.ndarray, gyr: np.ndarray | None, meta: Mapping[str, Any]) -> str | None:
    """The unit checks of acc (refuse) and gyr (refuse or a warning text, see :func:`check_gyr_unit`)."""
    return check_unit_magnitudes(
        acc_magnitude(acc), None if gyr is None else gyr_magnitude(gyr), meta, acc_mean_norm=acc_mean_norm(acc) if len(acc) else None
    )


def check_unit_magnitudes(
    acc_mag: np.ndarray, gyr_mag: np.ndarray | None, meta: Mapping[str, Any], *, acc_mean_norm: float | None = None
) -> str | None:
    """:func:`check_units` on the per-sample magnitudes (:func:`acc_magnitude`, :func:`gyr_magnitude`) and, when known,
    the norm of the mean acceleration vector (:func:`acc_mean_norm`; a file read in blocks sums its blocks)."""
    try:
        judge_acc_magnitude(acc_mag, mean_norm=acc_mean_norm)
    except InputError as exc:
        if "acc from g" in meta.get("converted", []):
            raise InputError(f"{exc} (the data was converted from g as asked: drop --acc-unit g / acc_unit='g' if it is in m/s^2)") from exc
        raise
    return None if gyr_mag is None else judge_gyr_magnitude(gyr_mag)


def convert_units(acc, gyr, acc_unit: str, gyr_unit: str):
    """``acc`` in m/s^2 and ``gyr`` in rad/s from the named units (InputError for a unit not in ACC_UNITS / GYR_UNITS)."""
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


def note_conversions(meta: dict, acc_unit: str, gyr_from_degs: bool) -> None:
    """Record in ``meta['converted']`` which unit conversions were applied."""
    conv = [c for c, applied in (("acc from g", acc_unit == "g"), ("gyr from deg/s", gyr_from_degs)) if applied]
    if conv:
        meta["converted"] = conv
