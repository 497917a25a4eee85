"""Step-to-step and slow variability: knots, speed drift, amplitude ~ speed^2, stride-time CV."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate import Subject, simulate_recording
from gaitml.simulate.variability import interpolate_knots, knot_index, speed_drift, speed_gain, step_knots


def test_knots_are_continuous_with_zero_slope_at_knots():
    rng = np.random.default_rng(0)
    idx = np.arange(20)
    knots = step_knots(rng, idx, 0.2, n_channels=2)
    mid, ev = knot_index(idx)
    phi = np.linspace(-0.5, 19.0, 20001)
    v = interpolate_knots(phi, knots)
    assert v.shape == (len(phi), 2)
    assert np.abs(np.diff(v, axis=0)).max() < 0.01  # no jumps on a fine grid
    # the value at a knot is the knot, and the slope there is zero
    at = interpolate_knots(np.array([5.0, 5.0 + 1e-4, 5.0 - 1e-4]), knots)
    assert at[0] == pytest.approx(knots[ev[5]])
    assert np.abs(at[1] - at[0]).max() < 1e-6 and np.abs(at[2] - at[0]).max() < 1e-6
    assert interpolate_knots(np.array([4.5]), knots)[0] == pytest.approx(knots[mid[5]])


def test_knot_spread_and_base():
    rng = np.random.default_rng(1)
    idx = np.arange(5000)
    k = step_knots(rng, idx, 0.1, base=2.0)
    mid, ev = knot_index(idx)
    assert np.log(k[ev, 0] / 2.0).std() == pytest.approx(0.1, rel=0.05)
    assert np.corrcoef(np.log(k[ev, 0]), np.log(k[mid, 0]))[0, 1] == pytest.approx(0.0, abs=0.05)


def test_speed_drift_is_slow_and_sized():
    f = speed_drift(np.random.default_rng(2), 600.0, 0.03, 5.0)
    t = np.arange(0, 600, 0.1)
    x = np.log(f(t))
    assert x.std() == pytest.approx(0.03, rel=0.05)
    # correlated over a second, not over a minute
    lag = lambda n: np.corrcoef(x[:-n], x[n:])[0, 1]  # noqa: E731
    assert lag(5) > 0.9 and lag(10) > 0.6 and abs(lag(600)) < 0.3


def test_amplitude_follows_speed_squared():
    assert speed_gain(np.array([1.0, 1.1, 0.9])) == pytest.approx([1.0, 1.21, 0.81])
    assert speed_gain(np.array([3.0]))[0] == pytest.approx(1.6)  # clipped


def test_stride_time_cv_stays_human():
    # step-time CV of the simulated walk: jitter 3 % plus the slow drift, about 3-6 % (real walks 3.5-4.4 %)
    rec = simulate_recording(Subject(), modes=("walk",), route="straight", duration_s=120.0, seed=0)
    st = rec.reference["steps"]
    dur = (st["t_s"] - st["t_start_s"]).to_numpy()[1:]
    dur = dur[dur < 0.75]  # drop the slower turning steps
    assert 0.02 < dur.std() / dur.mean() < 0.065


def test_no_variability_gives_the_old_regular_walk():
    steady = dataclasses.replace(
        Subject(), step_amp_cv=0.0, step_shape_cv=0.0, step_lateral_cv=0.0, speed_drift_cv=0.0, hand_jitter_drift=0.0
    )
    a = simulate_recording(steady, modes=("walk",), duration_s=30.0, seed=0)
    b = simulate_recording(steady, modes=("walk",), duration_s=30.0, seed=0)
    assert np.array_equal(a.acc, b.acc)


def test_subject_rejects_bad_variability():
    with pytest.raises(InputError, match="step_amp_cv"):
        Subject(step_amp_cv=-0.1)
    with pytest.raises(InputError, match="speed_drift_time_s"):
        Subject(speed_drift_time_s=0.0)
