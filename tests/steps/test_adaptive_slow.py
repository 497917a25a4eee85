"""adaptive at slow cadence and without gait (issue 30)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.simulate import Subject, simulate_recording
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector


def _slow_walk(seed: int, cadence_hz: float):
    rng = np.random.default_rng([seed, 31])
    s = Subject.random(rng, subject="SLOW", pose="flat")
    s = dataclasses.replace(
        s,
        walk_cadence_hz=cadence_hz,
        walk_step_length_m=0.4,
        walk_vertical_ms2=s.walk_vertical_ms2 * (cadence_hz / s.walk_cadence_hz) ** 2,
        walk_shoulder=0.5,
    )
    return simulate_recording(s, modes=["walk"], duration_s=40, seed=seed)


@pytest.mark.parametrize(("seed", "cadence_hz"), [(1, 0.8), (2, 0.95), (3, 1.1), (4, 1.2)])
def test_slow_walker_steps_are_not_taken_for_strides(seed, cadence_hz):
    rec = _slow_walk(seed, cadence_hz)
    n_true = rec.reference["n_steps_true"]
    n = len(get_detector("adaptive").detect(rec).steps_)
    assert abs(n - n_true) <= max(2, 0.03 * n_true)
    # the previous cadence range (from 1.2 steps/s) took each slow step for a stride
    if cadence_hz < 1.15:
        old = len(get_detector("adaptive", min_step_hz=1.2).detect(rec).steps_)
        assert old > 1.3 * n_true


def test_a_desk_phone_gives_no_confident_steps():
    for seed in range(3):
        st = get_detector("adaptive").detect(simulate_nongait("desk", duration_s=120, seed=seed)).steps_
        assert int(np.sum(st["confidence"] >= 0.5)) == 0


def test_gesture_bursts_lose_steps_and_confidence_to_the_short_bout_rule():
    rec = simulate_nongait("gestures", duration_s=120, seed=7)
    # the gait-evidence test (test_gait_evidence.py) is off: this checks the short-bout rule alone
    with_rule = get_detector("adaptive", gait_check=False).detect(rec).steps_
    without = get_detector("adaptive", short_bout_steps=0, gait_check=False).detect(rec).steps_
    assert len(with_rule) < 0.7 * len(without)
    walk = get_detector("adaptive").detect(_slow_walk(5, 1.0)).steps_
    assert with_rule["confidence"].median() < walk["confidence"].median()


@pytest.mark.parametrize(
    "bad",
    [
        {"short_bout_steps": -1},
        {"max_short_bout_cv": -0.1},
        {"slow_step_max_rms_ms2": -1.0},
        {"slow_step_hz": 0},
        {"slow_step_max_half_correlation": 1.5},
    ],
)
def test_new_parameters_are_checked(bad):
    from gaitml.errors import InputError

    with pytest.raises(InputError, match=next(iter(bad))):
        get_detector("adaptive", **bad).detect(_slow_walk(1, 1.0))


def _gentle_one_leg_walk(stride_s: float, seconds: float = 60.0, fs: float = 100.0):
    """|acc| of a trouser pocket on a gentle walk: the near leg's swing once per stride, a heel strike of each leg."""
    from gaitml.recording import Recording

    t = np.arange(0, seconds, 1 / fs)
    phase = (t / stride_s) % 1.0

    def pulse(centre, width=0.06):
        d = (phase - centre + 0.5) % 1.0 - 0.5
        return np.exp(-0.5 * (d * stride_s / width) ** 2)

    mag = 9.81 + 0.6 * np.sin(2 * np.pi * t / stride_s) + 1.6 * pulse(0.1) + 1.0 * pulse(0.6)
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), mag])
    return Recording.from_arrays(acc, fs), seconds / stride_s


@pytest.mark.parametrize("stride_s", [0.95, 1.1, 1.25])
def test_a_gentle_one_leg_stride_is_not_taken_for_a_slow_step(stride_s):
    """A stride of 0.83-1.33 s without deep anti-phase at its half is two steps (a tyrex back pocket, issue 30)."""
    rec, strides = _gentle_one_leg_walk(stride_s)
    det = get_detector("adaptive").detect(rec)
    assert float(det.cadence_["cadence_hz"].median()) == pytest.approx(2.0 / stride_s, rel=0.05)
    assert abs(len(det.steps_) - 2 * strides) <= max(4, 0.03 * 2 * strides)
    # without the anti-phase requirement the gentle stride (RMS below slow_step_max_rms_ms2) was one slow step
    off = get_detector("adaptive", slow_step_max_half_correlation=1.0).detect(rec).steps_
    assert len(off) < 0.7 * 2 * strides
