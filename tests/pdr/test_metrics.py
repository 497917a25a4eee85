"""Trajectory metrics (gaitml.evaluation.trajectory)."""

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.evaluation.trajectory import (
    absolute_trajectory_error,
    checkpoint_errors,
    closure_error,
    end_point_error,
    path_length,
    rigid_align_2d,
)


def test_end_point_and_closure_known_answers():
    xy = np.array([[0.0, 0.0], [0.0, 10.0], [10.0, 10.0], [10.0, 0.0], [3.0, 4.0]])
    assert path_length(xy) == pytest.approx(30.0 + np.hypot(7, 4))
    err, pct = end_point_error(xy, (0.0, 0.0), 40.0)
    assert err == pytest.approx(5.0) and pct == pytest.approx(12.5)
    err, pct = closure_error(xy)
    assert err == pytest.approx(5.0) and pct == pytest.approx(100 * 5.0 / path_length(xy))


def test_checkpoints_interpolate_in_time():
    t = np.array([0.0, 1.0, 2.0])
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    cp = pd.DataFrame({"t_s": [0.5, 2.0], "x_m": [0.5, 1.0], "y_m": [0.0, 2.0]})
    out = checkpoint_errors(t, xy, cp)
    assert np.allclose(out["error_m"], [0.0, 1.0])


def test_ate_with_rigid_alignment_removes_an_unknown_start_heading():
    rng = np.random.default_rng(0)
    t = np.linspace(0, 100, 300)
    truth = np.column_stack([np.cos(t / 20) * 30, np.sin(t / 15) * 20])
    a = 0.7
    r = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    est = truth @ r.T + [5.0, -3.0] + rng.normal(0, 0.01, truth.shape)
    assert absolute_trajectory_error(t, est, t, truth)["rmse_m"] > 5
    assert absolute_trajectory_error(t, est, t, truth, align="rigid")["rmse_m"] < 0.03
    R, tr = rigid_align_2d(est, truth)
    assert np.allclose(R, r.T, atol=1e-3)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: end_point_error(np.zeros((3, 2)), (0, 0), 0.0), "positive"),
        (lambda: end_point_error(np.zeros((3, 3)), (0, 0), 1.0), "shape"),
        (lambda: closure_error(np.zeros((3, 2))), "zero length"),
        (lambda: absolute_trajectory_error([0, 1], np.zeros((2, 2)), [0, 1], np.zeros((2, 2)), align="scale"), "align"),
        (lambda: checkpoint_errors([0, 1], np.zeros((2, 2)), pd.DataFrame({"t_s": [0]})), "x_m"),
    ],
)
def test_bad_inputs(call, match):
    with pytest.raises(InputError, match=match):
        call()
