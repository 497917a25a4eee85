"""experiments/scripts/tyrex_bpheading.py: the per-step truth rebuilds the walk, the heading helpers follow a known
rotation, and the paired table counts recording by recording (synthetic, no shared data)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.spatial.transform import Rotation

from experiments.scripts.tyrex_bpheading import horizontal_axis_heading, paired, projected_heading, rate_about, score_steps, step_truth


def _loop_walk(fs: float = 60.0, duration_s: float = 120.0, speed: float = 1.0, turn_rads: float = 0.4):
    """A walk round a circle (radius speed / turn) at the motion capture's rate: times, positions (x east, y north)."""
    t = np.arange(0.0, duration_s, 1.0 / fs)
    r = speed / turn_rads
    ang = turn_rads * t
    return t, np.column_stack([r * np.sin(ang), r * np.cos(ang)])


def test_true_lengths_and_headings_rebuild_the_walk():
    tt, xy = _loop_walk()
    t_step = np.arange(0.5, 119.0, 0.5)
    length, heading = step_truth(t_step, tt, xy)
    assert len(length) == len(heading) == len(t_step)
    assert np.median(length) == pytest.approx(0.5, rel=0.05)  # 1 m/s over 0.5 s
    s = score_steps(t_step, length, heading, float(tt[-1]), tt, xy)
    assert s["distance_ratio"] == pytest.approx(1.0, abs=0.05)
    assert s["error_10s_pct"] < 3.0
    assert abs(s["drift_deg_per_min"]) < 2.0


def test_a_heading_that_drifts_is_scored_as_drift_and_a_long_step_as_distance():
    tt, xy = _loop_walk()
    t_step = np.arange(0.5, 119.0, 0.5)
    length, heading = step_truth(t_step, tt, xy)
    drifted = heading + np.deg2rad(30.0) * t_step / 60.0  # 30 deg/min clockwise
    s = score_steps(t_step, length, drifted, float(tt[-1]), tt, xy)
    assert abs(s["drift_deg_per_min"]) == pytest.approx(30.0, abs=3.0)
    long = score_steps(t_step, 1.4 * length, heading, float(tt[-1]), tt, xy)
    assert long["distance_ratio"] == pytest.approx(1.4, abs=0.07)
    assert abs(long["drift_deg_per_min"]) < 2.0
    # 0.4 x the chord of 10 s round a 2.5 m circle (3.6 m) over the 10 m walked: about 14 %
    assert long["error_10s_pct"] > 10.0


def _steep_phone(n: int = 2000, fs: float = 100.0):
    """A phone whose y axis stands 70 deg above the horizontal, turning about the vertical at 0.3 rad/s, its
    pitch swinging +-15 deg at 1 Hz (a thigh): phone-to-nav rotations and the true compass heading of its turn."""
    t = np.arange(n) / fs
    yaw = 0.3 * t
    pitch = np.deg2rad(70.0 + 15.0 * np.sin(2 * np.pi * t))
    rot = Rotation.from_euler("z", yaw[:, None]) * Rotation.from_euler("x", pitch[:, None])
    return t, rot, -yaw  # compass heading is clockwise


def test_the_horizontal_axis_follows_the_turn_and_is_horizontal_at_the_mean_attitude():
    t, rot, compass = _steep_phone()
    m = rot.as_matrix()
    h = np.unwrap(horizontal_axis_heading(m))
    # it turns with the phone (a constant offset aside) whatever the pitch swing
    np.testing.assert_allclose(h - h[0], compass - compass[0], atol=1e-6)
    # the y axis does too here (the swing is in its own vertical plane), and both share the compass convention
    hy = np.unwrap(projected_heading(m, (0.0, 1.0, 0.0)))
    np.testing.assert_allclose(hy - hy[0], compass - compass[0], atol=1e-6)


def test_the_horizontal_axis_needs_an_axis_off_the_mean_up():
    m = np.repeat(np.eye(3)[None], 10, axis=0)  # phone flat: up is its z axis
    with pytest.raises(ValueError, match="along the mean up"):
        horizontal_axis_heading(m, (0.0, 0.0, 1.0))


def test_rate_about_up_integrates_a_turn_clockwise_positive():
    fs = 100.0
    n = 1001
    up = np.tile([0.0, 0.0, 1.0], (n, 1))
    w = np.tile([0.0, 0.0, 0.2], (n, 1))  # counter-clockwise about up
    psi = rate_about(w, up, fs)
    assert psi[0] == 0.0
    assert psi[-1] == pytest.approx(-0.2 * (n - 1) / fs)
    # a rate about a horizontal axis turns nothing
    assert np.allclose(rate_about(np.tile([0.3, 0.0, 0.0], (n, 1)), up, fs), 0.0)


def test_paired_counts_recording_by_recording():
    rows = []
    for i, (a, b) in enumerate([(10.0, 5.0), (-20.0, 30.0), (8.0, -4.0), (3.0, 3.0)]):
        rows += [
            {"file": f"r{i}", "motion": "BackPocket", "variant": "gaitml", "drift_deg_per_min": a},
            {"file": f"r{i}", "motion": "BackPocket", "variant": "other", "drift_deg_per_min": b},
        ]
    out = paired(pd.DataFrame(rows), "other")
    row = out.loc["BackPocket"]
    assert row["recordings"] == 4
    assert row["lower"] == 2  # |5| < |10|, |-4| < |8|
    assert row["higher"] == 1  # |30| > |-20|
    assert row["median difference"] == pytest.approx(np.median([-5.0, 10.0, -4.0, 0.0]))
    assert row["mean gaitml"] == pytest.approx(np.mean([10, 20, 8, 3]))
