"""experiments.scripts.front_pocket_dynamics: the candidate descriptors and the two rules."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts import front_pocket_dynamics as fp

FS = 50.0


def _walk(rotation_period_s: float, seconds: float = 12.0, step_s: float = 0.48):
    """Gravity on z with a vertical bounce once per step, a rotation about x with the given period, a little noise."""
    t = np.arange(int(seconds * FS)) / FS
    rng = np.random.default_rng(3)
    acc = np.zeros((len(t), 3))
    acc[:, 2] = 9.81 + 2.0 * np.cos(2 * np.pi * t / step_s)
    acc += 0.02 * rng.normal(size=acc.shape)
    gyr = 0.02 * rng.normal(size=acc.shape)
    gyr[:, 0] += 1.5 * np.cos(2 * np.pi * t / rotation_period_s)
    starts = np.arange(0, len(t) - 75 + 1, 37)
    return acc, gyr, starts, starts + 75


def test_the_candidates_are_unchanged_by_a_constant_rotation():
    acc, gyr, s, e = _walk(0.96)
    R = fp._random_rotation(np.random.default_rng(11))
    a = fp.candidate_dynamics(acc, gyr, s, e, FS)
    b = fp.candidate_dynamics(acc @ R.T, gyr @ R.T, s, e, FS)
    assert a.shape == (len(s), len(fp.CANDIDATE_NAMES)) and np.isfinite(a).all()
    np.testing.assert_allclose(a, b, atol=1e-9)


def test_a_rotation_once_per_stride_and_once_per_step():
    col = {n: i for i, n in enumerate(fp.CANDIDATE_NAMES)}
    stride = fp.candidate_dynamics(*_walk(0.96), FS)  # turns once per two steps (a thigh)
    step = fp.candidate_dynamics(*_walk(0.48), FS)  # turns once per step
    assert np.median(stride[:, col["gyr_autocorr_step"]]) < -0.8
    assert np.median(step[:, col["gyr_autocorr_step"]]) > 0.8
    assert np.median(stride[:, col["gyr_log_stride_step_power"]]) > 2.0
    assert np.median(step[:, col["gyr_log_stride_step_power"]]) < -2.0
    # the angle turned at 1.5 rad/s with a 0.96 s period: amplitude 1.5 * 0.96 / 2 pi rad (13.1 deg), its spread over
    # whole periods 13.1 / sqrt 2 = 9.3 deg (a 1.5 s window holds about 1.6 periods)
    swept = np.exp(np.median(stride[:, col["log_swept_angle_deg"]]))
    assert 8.0 < swept < 11.0


def _table(front: float, others: float, false_alarms: float) -> dict:
    return {fp.FRONT: front, **{o: others for o in fp.OTHERS}, "mean false alarms": false_alarms}


def test_the_selection_rule_takes_the_best_front_pocket_that_keeps_the_others():
    df = pd.DataFrame(
        {
            "current": _table(0.75, 0.95, 0.001),
            "+a": _table(0.90, 0.90, 0.001),  # the others drop 5 points
            "+b": _table(0.85, 0.94, 0.02),  # too many false alarms
            "+c": _table(0.80, 0.935, 0.005),
        }
    ).T
    assert fp.choose(df) == "+c"
    assert fp.choose(df.loc[["current", "+a"]]) == "current"


def test_the_adoption_rule():
    base = _table(0.67, 0.95, 0.008)
    ok, why = fp.adopt(pd.DataFrame({"current": base, "+c": _table(0.81, 0.94, 0.012)}).T, "+c")
    assert ok and not why
    ok, why = fp.adopt(pd.DataFrame({"current": base, "+c": _table(0.79, 0.99, 0.001)}).T, "+c")
    assert not ok and why == ["front pocket 79.0 % < 80 %"]
    ok, why = fp.adopt(pd.DataFrame({"current": base, "+c": _table(0.85, 0.92, 0.014)}).T, "+c")
    assert not ok and len(why) == len(fp.OTHERS) + 1
    assert fp.adopt(pd.DataFrame({"current": base}).T, "current")[0] is False
