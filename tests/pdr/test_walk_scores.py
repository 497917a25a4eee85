"""Walk scores for looping walks in a small room (gaitml.evaluation.trajectory.walk_scores and parts)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.evaluation.trajectory import (
    body_track,
    displacement_errors,
    walk_scores,
    walked_distance_ratio,
    walking_direction_drift,
)

FS = 60.0


def loop_walk(duration_s=120.0, speed_ms=1.0, radius_m=2.0, swing_m=0.0, swing_hz=1.8):
    """A body walking round a circle (counter-clockwise), the phone swinging along the path by ``swing_m``."""
    t = np.arange(0, duration_s, 1 / FS)
    a = speed_ms * t / radius_m
    body = np.column_stack([radius_m * np.cos(a), radius_m * np.sin(a)])
    tangent = np.column_stack([-np.sin(a), np.cos(a)])
    phone = body + swing_m * np.sin(2 * np.pi * swing_hz * t)[:, None] * tangent
    return t, body, phone


def rotate(xy, angle):
    c, s = np.cos(angle), np.sin(angle)
    return xy @ np.array([[c, -s], [s, c]]).T


def test_body_track_removes_the_phone_swing():
    t, body, phone = loop_walk(swing_m=0.25)
    raw = np.linalg.norm(np.diff(phone, axis=0), axis=1).sum()
    true = np.linalg.norm(np.diff(body, axis=0), axis=1).sum()
    low = np.linalg.norm(np.diff(body_track(t, phone), axis=0), axis=1).sum()
    assert raw > 1.3 * true  # the swing overstates the walk ...
    assert low == pytest.approx(true, rel=0.03)  # ... the low-passed track does not


def test_distance_ratio_sees_a_scale_error_and_ignores_the_swing():
    t, body, phone = loop_walk(swing_m=0.25)
    est = 1.2 * rotate(body, 0.7) + 3.0
    out = walked_distance_ratio(t[::30], est[::30], t, phone)
    assert out["ratio"] == pytest.approx(1.2, rel=0.03)
    assert out["true_m"] == pytest.approx(120.0, rel=0.03)


def test_a_rotated_shifted_estimate_has_no_displacement_error():
    t, body, phone = loop_walk()
    est = rotate(body, 2.0) + [5.0, -1.0]
    win = displacement_errors(t[::6], est[::6], t, phone)
    assert len(win) > 100
    assert win["error_pct"].max() < 1.0
    assert win.attrs["alignment"]["angle_rad"] == pytest.approx(-2.0, abs=0.01)


def test_still_trajectory_scores_chord_over_arc():
    """Standing still, the 10 s displacement error is the chord over the arc walked: known answer on a circle."""
    r, v, w = 2.0, 1.0, 10.0
    t, _, phone = loop_walk(radius_m=r, speed_ms=v)
    s = walk_scores([0.0, t[-1]], np.zeros((2, 2)), t, phone, window_s=w)
    theta = v * w / r
    expect = 100 * 2 * r * abs(np.sin(theta / 2)) / (v * w)
    assert s["error_10s_pct"] == pytest.approx(expect, rel=0.03)
    assert s["distance_ratio"] == 0.0
    assert np.isnan(s["drift_deg_per_min"])


def test_heading_drift_is_measured_and_counts_in_the_10s_error():
    t, body, phone = loop_walk(radius_m=3.0)
    drift_deg_min = 30.0
    # the estimate's walking direction turns away from the truth at a steady rate
    step = np.diff(body, axis=0)
    ang = np.radians(drift_deg_min / 60.0) * t[1:]
    c, s = np.cos(ang), np.sin(ang)
    step_r = np.column_stack([c * step[:, 0] - s * step[:, 1], s * step[:, 0] + c * step[:, 1]])
    est = np.vstack([body[:1], body[0] + np.cumsum(step_r, axis=0)])
    d = walking_direction_drift(t[::6], est[::6], t, phone)
    assert d["drift_deg_per_min"] == pytest.approx(drift_deg_min, rel=0.05)
    good = walk_scores(t[::6], body[::6], t, phone)
    bad = walk_scores(t[::6], est[::6], t, phone)
    assert good["error_10s_pct"] < 1.0
    # after two minutes at 30 deg/min the late windows are off by ~ 2 sin(30 deg) = 100 %
    assert bad["error_10s_pct"] > 20.0


def test_lost_markers_are_filled_and_bad_tracks_refused():
    t, body, phone = loop_walk()
    lost = phone.copy()
    lost[300:320] = np.nan
    assert walked_distance_ratio(t, body, t, lost)["ratio"] == pytest.approx(1.0, rel=0.01)
    with pytest.raises(InputError, match="uniform rate"):
        walked_distance_ratio(t, body, np.sort(np.random.default_rng(0).uniform(0, 120, len(t))), phone)
    with pytest.raises(InputError, match="do not overlap"):
        walked_distance_ratio(t + 1000, body, t, phone)
