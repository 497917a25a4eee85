"""A fixed physics rule that flags a window resting between fast swings, as a foot-mounted (shoe-mounted) sensor does at every stride.

The rule sees a motion pattern, not a placement: a window holding a rest between fast swings is
what a foot shows at every stride of a walk, and what no phone carried by a walker shows; a hand
that gestures with the phone (fast turns with pauses between, not walking) can show it too. The
reason it gives (:data:`FOOT_REASON`) therefore says what was seen and names the foot as a
question. Such a window is out of domain for a model trained on carried phones either way: a
gesture is none of the motion modes.

A motion-mode model trained on phones carried in the hand, a pocket or a bag has never seen a
sensor on the foot. The foot, unlike every place a phone is carried, *rests* once per stride:
in the foot-flat part of each stance it lies still on the ground while the body passes over it
(the zero-velocity premise of foot-mounted pedestrian navigation: paper 001 sec. 1, paper 004
sec. 2), and between two rests it swings forward, rotating from its toe-off pitch to its
heel-strike pitch within a few tenths of a second. A phone in the hand, a pocket, a bag or on a
belt rides on the trunk, a thigh or an arm, which keep moving all through the stride: the thigh
rotates through the whole stance, an arm or a hanging bag swings through it and turns round only
for an instant, and the trunk bounces at every step.

The rule, per window (its own samples only, so a recording cut into chunks at the rate it is
classified at gives every window the same answer; a recording resampled chunk by chunk to the
model's rate can differ near the thresholds, as its resampled samples differ at the chunks' edges):

- a sample *rests* when its angular rate is below :data:`REST_GYR_RADS` and its acceleration
  magnitude lies within :data:`REST_ACC_TOL_MS2` of gravity (the stance tests of foot-mounted
  navigation on the angular rate and the acceleration magnitude, as in :mod:`gaitml.zupt`);
- a *stance rest* is a run of resting samples lasting :data:`MIN_REST_S` to :data:`MAX_REST_S`
  that lies inside the window with motion on both sides (it touches neither window edge: a
  walker who stops, or starts, rests up to the edge and is not counted);
- the window *swings* when its largest angular rate reaches :data:`SWING_GYR_RADS`;
- the gyroscope test holds when the window holds a stance rest and swings.

The accelerometer test reads the acceleration alone: a sample rests when its acceleration
magnitude lies within :data:`REST_ACC_TOL_MS2` of gravity and varies by less than
:data:`REST_ACC_STD_MS2` (standard deviation over :data:`REST_STD_WINDOW_S` around it); a stance
rest lasts :data:`ACC_MIN_REST_S` to :data:`MAX_REST_S`; the window swings when its acceleration
magnitude reaches :data:`SWING_ACC_MS2` (the heel strike and push-off).

A window is **foot-like** when either test holds (without a gyroscope: the accelerometer test).

This is ours (the papers detect stances on a foot they know is instrumented; none tells a foot
from a phone). The thresholds are stated from the physics below; where the physics leaves a
range (the shortest stance rest, the swing rates) the value was chosen on the simulator's foot
(:func:`gaitml.simulate.foot.simulate_foot`) and phone positions, never on real recordings.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.consts import GRAVITY_MS2

__all__ = [
    "ACC_MIN_REST_S",
    "FOOT_REASON",
    "MAX_REST_S",
    "MIN_REST_S",
    "REST_ACC_STD_MS2",
    "REST_ACC_TOL_MS2",
    "REST_GYR_RADS",
    "REST_STD_WINDOW_S",
    "SWING_ACC_MS2",
    "SWING_GYR_RADS",
    "PLACEMENT_PREFIX",
    "foot_like_windows",
    "min_window_samples",
    "rest_samples",
]

#: The stable, machine-readable start of every reason this rule gives.
PLACEMENT_PREFIX = "placement:"
#: The reason given for a window the rule flags (table column ``out_of_domain_reason``, JSON, warning): what was seen,
#: and the placement it suggests as a question (a gesturing hand can show the same pattern).
FOOT_REASON = f"{PLACEMENT_PREFIX} rests between fast swings (foot-mounted sensor?)"
#: A resting sample turns slower than 0.5 rad/s (29 deg/s): a foot flat on the ground turns only by
#: the gyroscope's noise and bias (a few deg/s); the same bound as the gyro-range stance test
#: (:data:`gaitml.zupt.gyro_range.DEFAULT_GYR_RANGE_RADS`).
REST_GYR_RADS = 0.5
#: A resting sample's acceleration magnitude lies within this (m/s^2) of gravity: a foot flat on the
#: ground measures gravity alone (plus noise and a scale error of a few per cent at most); the
#: same margin as the gyro-range stance test's g + 0.5 m/s^2.
REST_ACC_TOL_MS2 = 0.5
#: Shortest stance rest (s) with a gyroscope. A walking foot lies flat for about a quarter of its
#: stride (loading response to heel rise; Perry & Burnfield, *Gait Analysis*, 2010): 0.2-0.35 s at
#: strides of 0.9-1.4 s. A limb or a hanging bag that swings at :data:`SWING_GYR_RADS` turns round
#: for an instant only: a rotation of peak rate W at a stride rate f >= 0.7 Hz stays below
#: :data:`REST_GYR_RADS` for about 2 arcsin(0.5 / W) / (2 pi f) <= 0.06 s. The value between
#: (0.12-0.2 s bracket it) was chosen on the simulator (experiments/reports/foot-placement.md).
MIN_REST_S = 0.14
#: Longest stance rest (s): the foot flat of the slowest walking stride (about a quarter of a
#: 2.5 s stride, :data:`gaitml.zupt._intervals.STRIDE_RANGE_S`) with a margin. A longer rest
#: between two swings is a pause, not a stance.
MAX_REST_S = 0.8
#: A swinging foot rotates from its toe-off pitch (50-65 deg toe down) to its heel-strike pitch
#: (15-25 deg toe up; Perry & Burnfield 2010) in a swing of 0.35-0.5 s: at least 65 deg in 0.5 s, a
#: mean of 2.3 rad/s, and a smooth (minimum-jerk) rotation peaks at 1.875 times its mean, 4.3 rad/s.
#: A window of walking on the foot reaches 4 rad/s at every swing.
SWING_GYR_RADS = 4.0
#: Accelerometer-only rule: a resting sample's acceleration magnitude varies by less than this
#: (standard deviation, m/s^2) over :data:`REST_STD_WINDOW_S` around it (a foot flat on the
#: ground: sensor noise; a phone on a walker: the body's bounce, about 1-3 m/s^2 at 2 Hz).
REST_ACC_STD_MS2 = 0.3
#: Window (s) of that standard deviation (paper 001's 0.1 s window of its stance statistic).
REST_STD_WINDOW_S = 0.1
#: Accelerometer-only rule: shortest stance rest (s): paper 004 sec. 2.2 step (4) takes
#: acceleration-magnitude rests shorter than a tenth of a second for pseudo-rests.
ACC_MIN_REST_S = 0.1
#: Accelerometer-only rule: the window swings when its acceleration magnitude reaches this (m/s^2):
#: a walking foot's heel strike and push-off peak at 2-3 g; a walker's trunk or thigh stays
#: below about 2 g.
SWING_ACC_MS2 = 2.5 * GRAVITY_MS2


def min_window_samples(sampling_rate_hz: float) -> int:
    """The fewest samples a window needs for the rule to be able to flag it: its shortest stance rest and one moving sample either side."""
    shortest = min(MIN_REST_S, ACC_MIN_REST_S)
    return int(np.ceil(shortest * float(sampling_rate_hz) - 1e-9)) + 2


def _magnitude(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.sqrt(np.einsum("ij,ij->i", x, x))


def _std_half(sampling_rate_hz: float) -> int:
    """Half-width (samples) of the standard deviation of the accelerometer test's rest: :data:`REST_STD_WINDOW_S` in all."""
    return max(1, int(round(0.5 * REST_STD_WINDOW_S * sampling_rate_hz)))


def rest_samples(
    acc: np.ndarray,
    gyr: np.ndarray | None,
    sampling_rate_hz: float,
    *,
    rest_gyr_rads: float = REST_GYR_RADS,
    rest_acc_tol_ms2: float = REST_ACC_TOL_MS2,
    rest_acc_std_ms2: float = REST_ACC_STD_MS2,
) -> np.ndarray:
    """Which samples rest: angular rate and acceleration magnitude, or (``gyr`` None) the acceleration alone (module docstring)."""
    a = _magnitude(acc)
    if gyr is not None:
        return _gyro_rest(a, _magnitude(gyr), rest_gyr_rads, rest_acc_tol_ms2)
    return _acc_rest(a, sampling_rate_hz, rest_acc_tol_ms2, rest_acc_std_ms2)


def _gyro_rest(a: np.ndarray, w: np.ndarray, rest_gyr_rads: float, rest_acc_tol_ms2: float) -> np.ndarray:
    """The gyroscope test's rest of each sample from the magnitudes ``a`` (m/s^2) and ``w`` (rad/s)."""
    return (np.abs(a - GRAVITY_MS2) < rest_acc_tol_ms2) & (w < rest_gyr_rads)


def _acc_rest(a: np.ndarray, sampling_rate_hz: float, rest_acc_tol_ms2: float, rest_acc_std_ms2: float) -> np.ndarray:
    """The accelerometer test's rest of each sample from the magnitude ``a``: near g and steady around it (centred window)."""
    dev = a - GRAVITY_MS2
    rest = np.abs(dev) < rest_acc_tol_ms2
    n = len(a)
    half = _std_half(sampling_rate_hz)
    if n == 0:
        return rest
    c1 = np.concatenate(([0.0], np.cumsum(dev)))
    c2 = np.concatenate(([0.0], np.cumsum(dev * dev)))
    var = np.empty(n)
    k = 2 * half + 1
    if n >= k:  # the centred windows inside the recording, by slices
        mean = (c1[k:] - c1[:-k]) / k
        var[half : n - half] = (c2[k:] - c2[:-k]) / k - mean * mean
    edge = np.r_[0 : min(half, n), max(n - half, min(half, n)) : n] if n >= k else np.arange(n)
    lo, hi = np.maximum(edge - half, 0), np.minimum(edge + half + 1, n)  # clipped at the recording's ends
    mean = (c1[hi] - c1[lo]) / (hi - lo)
    var[edge] = (c2[hi] - c2[lo]) / (hi - lo) - mean * mean
    return rest & (var < rest_acc_std_ms2 * rest_acc_std_ms2)


def _stance_rests(rest: np.ndarray, fs: float, start: np.ndarray, end: np.ndarray, min_rest_s: float, max_rest_s: float) -> np.ndarray:
    """How many runs of ``rest`` lasting ``min_rest_s`` to ``max_rest_s`` lie strictly inside each window ``[start, end)``."""
    d = np.diff(np.concatenate(([False], rest, [False])).astype(np.int8))
    rs, re = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    dur = (re - rs) / float(fs)
    ok = (dur >= min_rest_s - 1e-9) & (dur <= max_rest_s + 1e-9)
    cum_ok = np.concatenate(([0], np.cumsum(ok)))
    # the runs strictly inside [start, end): from the first starting after `start` to the last ending before `end`
    i0 = np.searchsorted(rs, start, side="right")
    i1 = np.searchsorted(re, end, side="left")
    return np.where(i1 > i0, cum_ok[np.maximum(i1, i0)] - cum_ok[i0], 0).astype(np.int64)


def _reaches(mag: np.ndarray, level: float, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Whether the magnitude ``mag`` reaches ``level`` anywhere in each window ``[start, end)``."""
    cum = np.concatenate(([0], np.cumsum(mag >= level)))
    return (cum[end] - cum[start]) > 0


def foot_like_windows(
    acc: np.ndarray,
    gyr: np.ndarray | None,
    sampling_rate_hz: float,
    windows: pd.DataFrame,
    *,
    rest_gyr_rads: float = REST_GYR_RADS,
    rest_acc_tol_ms2: float = REST_ACC_TOL_MS2,
    rest_acc_std_ms2: float = REST_ACC_STD_MS2,
    min_rest_s: float = MIN_REST_S,
    acc_min_rest_s: float = ACC_MIN_REST_S,
    max_rest_s: float = MAX_REST_S,
    swing_gyr_rads: float = SWING_GYR_RADS,
    swing_acc_ms2: float = SWING_ACC_MS2,
) -> dict[str, np.ndarray]:
    """The foot-mounted-sensor rule of every window (``start``, ``end`` samples): see the module docstring.

    Two tests, each a stance rest inside the window plus a swing: the gyroscope test (rest: slow
    rotation and gravity alone; swing: :data:`SWING_GYR_RADS`) and the accelerometer test (rest:
    gravity alone, steady; swing: :data:`SWING_ACC_MS2`). A window is foot-like when either holds
    (without a gyroscope: the accelerometer test). The accelerometer test does not read the
    gyroscope, so a gyroscope with a large uncorrected bias (a rest that never turns slower than
    :data:`REST_GYR_RADS`) does not hide a foot from it.

    Parameters
    ----------
    acc, gyr : (n, 3) arrays, m/s^2 and rad/s (``gyr`` None: the accelerometer test alone).
    sampling_rate_hz : float
    windows : DataFrame with ``start``, ``end`` (end exclusive).
    The keywords default to the module's constants.

    Returns
    -------
    dict
        One entry per window: ``foot_like`` (bool), ``gyro_test`` and ``acc_test`` (bool: each
        test; ``gyro_test`` all False without a gyroscope).
    """
    n = len(acc)
    if len(windows) == 0:
        return {k: np.zeros(0, bool) for k in ("foot_like", "gyro_test", "acc_test")}
    start = np.clip(windows["start"].to_numpy(dtype=np.int64), 0, n)
    end = np.clip(windows["end"].to_numpy(dtype=np.int64), start, n)
    fs = float(sampling_rate_hz)
    a = _magnitude(acc)
    rest_a = _acc_rest(a, fs, rest_acc_tol_ms2, rest_acc_std_ms2)
    # a rest sample's standard deviation reads `half` samples either side: the test's rests lie inside the window by that
    # much, so that it reads the window's own samples only (a recording cut into chunks gives every window the same answer)
    half = _std_half(fs)
    a_start = np.minimum(start + half, end)
    a_end = np.maximum(end - half, a_start)
    rests_a = _stance_rests(rest_a, fs, a_start, a_end, acc_min_rest_s, max_rest_s)
    acc_test = (rests_a > 0) & _reaches(a, swing_acc_ms2, start, end)
    if gyr is None:
        gyro_test = np.zeros(len(start), dtype=bool)
    else:
        w = _magnitude(gyr)
        rest_g = _gyro_rest(a, w, rest_gyr_rads, rest_acc_tol_ms2)
        gyro_test = (_stance_rests(rest_g, fs, start, end, min_rest_s, max_rest_s) > 0) & _reaches(w, swing_gyr_rads, start, end)
    return {"foot_like": gyro_test | acc_test, "gyro_test": gyro_test, "acc_test": acc_test}
