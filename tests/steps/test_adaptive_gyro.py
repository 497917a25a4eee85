"""adaptive's gyroscope check of the stride-versus-step decision (stage 2b)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.recording import Recording
from gaitml.steps import get_detector
from gaitml.steps.adaptive import swing_correlation
from tests.conftest import shared


def _phone(mag: np.ndarray, swing_rads: np.ndarray, fs: float, seed: int = 0) -> Recording:
    """|acc| along z, the swing rate about x, with a little sensor noise on every axis."""
    rng = np.random.default_rng(seed)
    n = len(mag)
    acc = np.column_stack([np.zeros(n), np.zeros(n), mag]) + rng.normal(0, 0.05, (n, 3))
    gyr = np.column_stack([swing_rads, np.zeros(n), np.zeros(n)]) + rng.normal(0, 0.01, (n, 3))
    return Recording.from_arrays(acc, fs, gyr=gyr)


def _swinging_hand(step_s=0.9, seconds=60.0, fs=100.0, swing_amp_rads=2.0):
    """A hand swinging once per stride: |acc| peaks at both ends of the swing (once per step), vigorously."""
    t = np.arange(int(seconds * fs)) / fs
    mag = 9.81 + 3.0 * np.cos(2 * np.pi * t / step_s)
    return _phone(mag, swing_amp_rads * np.sin(np.pi * t / step_s), fs), seconds / step_s


def _running_thigh(stride_s=0.7, seconds=60.0, fs=100.0):
    """A pocket phone on a running thigh: a strong |acc| cycle per stride (the near leg), a weaker one per step, the thigh swinging once per stride."""
    t = np.arange(int(seconds * fs)) / fs
    mag = 9.81 + 4.0 * np.cos(2 * np.pi * t / stride_s) + 1.5 * np.cos(4 * np.pi * t / stride_s)
    return _phone(mag, 2.5 * np.sin(2 * np.pi * t / stride_s), fs), 2 * seconds / stride_s


def test_swing_correlation_reads_phase_of_the_principal_axis():
    fs, L = 25.0, 125
    t = np.arange(400) / fs
    period = 1.6  # s
    g = np.column_stack([np.sin(2 * np.pi * t / period), 0.1 * np.cos(2 * np.pi * t / period), np.zeros_like(t)])
    k = period * fs
    rms, c = swing_correlation(g, L, 25, 5, np.tile([k / 2, k], (5, 1)))
    assert np.all(rms > 0.6)
    assert np.all(c[:, 0] < -0.9)  # half a cycle later: anti-phase
    assert np.all(c[:, 1] > 0.9)  # one cycle later: in phase


def test_a_swinging_hand_is_counted_per_step_with_the_gyroscope():
    rec, n_true = _swinging_hand()
    det = get_detector("adaptive").detect(rec)
    assert abs(len(det.steps_) - n_true) <= max(2, 0.03 * n_true)
    assert (det.cadence_["gyro"] == -1).mean() > 0.8
    # the accelerometer alone takes the vigorous 0.9 s period for a stride (above slow_step_max_rms_ms2)
    alone = get_detector("adaptive", use_gyroscope=False).detect(rec).steps_
    assert abs(len(det.steps_) - n_true) <= abs(len(alone) - n_true)  # the gyroscope never makes the count worse here


def test_a_running_thigh_is_counted_per_step_with_the_gyroscope():
    rec, n_true = _running_thigh()
    det = get_detector("adaptive").detect(rec)
    assert abs(len(det.steps_) - n_true) <= max(2, 0.03 * n_true)
    assert (det.cadence_["gyro"] == 1).mean() > 0.8
    alone = get_detector("adaptive", use_gyroscope=False).detect(rec).steps_
    assert abs(len(det.steps_) - n_true) <= abs(len(alone) - n_true)


def test_a_still_gyroscope_gives_no_verdict_but_lifts_the_motion_ceiling():
    # a vigorous 0.9 s |acc| cycle on a phone that does not turn (under gyro_min_rms_rads): no swing verdict, and no
    # swinging thigh or arm either, so the period is a slow step whatever the motion (the accelerometer alone, above
    # slow_step_max_rms_ms2, takes it for a stride)
    rec, n_true = _swinging_hand(swing_amp_rads=0.05)
    with_gyr = get_detector("adaptive").detect(rec)
    alone = get_detector("adaptive", use_gyroscope=False).detect(rec)
    assert (with_gyr.cadence_["gyro"] == 0).all()
    assert abs(len(with_gyr.steps_) - n_true) <= max(2, 0.03 * n_true)
    assert abs(len(with_gyr.steps_) - n_true) <= abs(len(alone.steps_) - n_true)


@pytest.mark.parametrize("bad", [{"gyro_min_rms_rads": -0.1}, {"gyro_phase_correlation": 1.5}, {"use_gyroscope": "yes"}])
def test_bad_gyroscope_settings_are_refused(bad):
    from gaitml.errors import InputError

    rec, _ = _swinging_hand(seconds=20.0)
    with pytest.raises((InputError, ValueError, TypeError)):
        get_detector("adaptive", **bad).detect(rec)


# The motion-capture step counts of two tyrex recordings, by the reference rule of experiments/scripts/tyrex_steps.py
# (the phone's swing tilt, one stride per swing; checked by eye in experiments/reports/tyrex-steps.md).
TYREX_REFERENCE = {
    "Jakob_iPhone4S_NoDist_Swinging": 128,  # a slow walker (1.1 steps/s) swinging the phone vigorously
    "Guillaume_iPhone4S_NoDist_RunningHand": 318,  # a running arm whose |acc| shows one event per stride
}


@pytest.mark.parametrize("name", sorted(TYREX_REFERENCE))
def test_tyrex_arm_swing_with_the_gyroscope(name):
    from gaitml.io.tyrex import read_tyrex, read_tyrex_truth

    folder = shared("tyrex-attitude", "ios", name)
    truth = read_tyrex_truth(folder)
    ok = truth.valid
    t0, t1 = float(truth.t_s[ok][0]), float(truth.t_s[ok][-1])
    recs = read_tyrex(folder, segments=True)
    recs = recs if isinstance(recs, list) else [recs]
    n_ref = TYREX_REFERENCE[name]

    def count(**kw):
        n = 0
        for r in recs:
            st = get_detector("adaptive", **kw).detect(r).steps_
            tt = float(r.meta.get("t0_original_s", 0.0)) + st["t_peak_s"].to_numpy()
            n += int(np.sum((tt >= t0) & (tt <= t1)))
        return n

    n = count()
    # the reference is good to about one stride in 20 on limb motions: a floor of 0.95
    assert abs(n - n_ref) / n_ref <= 0.05
    # the accelerometer alone misses by a fifth or more on these two (stride taken for a step or the reverse)
    assert abs(count(use_gyroscope=False) - n_ref) / n_ref > 0.15
