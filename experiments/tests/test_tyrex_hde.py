"""The candidate HDE structure guard of experiments/scripts/tyrex_hde.py on synthetic walks: a loop round a room
(no dominant directions: HDE's rate fit is spurious, the guard keeps the gyro heading), a corridor route with a
gyro drift (the guard lets HDE remove it), and headings without structure (false alarms near alpha)."""

from __future__ import annotations

import numpy as np

from experiments.scripts.tyrex_hde import STRUCTURE_ALPHA, direction_structure, guarded_hde
from gaitml.pdr.attitude import wrap_angle
from gaitml.pdr.hde import estimate_drift_rate, hde_heading


def _loop_walk(seed: int, n: int = 220, step_s: float = 0.55):
    """Steps round a 5 m room: the heading turns 0.3-0.6 rad/s (a loop every 10-20 s), varying, plus step noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * step_s
    turn = 0.45 + 0.15 * np.sin(2 * np.pi * t / rng.uniform(20, 40) + rng.uniform(0, 2 * np.pi))
    truth = np.cumsum(turn * step_s) + rng.uniform(-np.pi, np.pi)
    return t, truth, truth + rng.normal(0, np.deg2rad(3), n)


def test_on_loop_walks_the_fitted_rate_is_spurious_and_the_guard_keeps_the_gyro_heading():
    spurious, passed = [], 0
    for seed in range(20):
        t, _, raw = _loop_walk(seed)  # no gyro drift at all: every fitted rate is wrong
        dur = np.full(len(t), 0.55)
        spurious.append(abs(estimate_drift_rate(raw, t)))
        h, g = guarded_hde(raw, dur, t)
        passed += g["structured"]
        if not g["structured"]:
            assert np.array_equal(h, raw)
            assert g["statistic"] < g["threshold"]
    # HDE as shipped removes a rate it made up (median tens of deg/min); the guard holds it off
    assert np.rad2deg(np.median(spurious)) * 60 > 20.0
    assert passed <= 2


def test_on_a_corridor_route_the_guard_lets_hde_remove_the_drift():
    n = 400
    t = np.arange(n) * 0.5
    truth = np.repeat(np.deg2rad([0.0, 90.0, 180.0, 270.0]), n // 4)
    rng = np.random.default_rng(1)
    raw = wrap_angle(truth + 0.02 * t + rng.normal(0, np.deg2rad(2), n))  # 0.02 rad/s: an uncalibrated gyro
    dur = np.full(n, 0.5)
    h, g = guarded_hde(raw, dur, t)
    assert g["structured"] and g["statistic"] > 2 * g["threshold"]
    assert np.array_equal(h, hde_heading(raw, dur, t)[0])
    assert np.degrees(np.median(np.abs(wrap_angle(h - truth)))) < 3.0
    assert np.degrees(np.median(np.abs(wrap_angle(raw - truth)))) > 30.0


def test_headings_without_structure_pass_at_most_about_alpha():
    rng = np.random.default_rng(0)
    t = np.arange(150) * 0.5
    hits = 0
    for _ in range(300):
        u = rng.uniform(-np.pi, np.pi, len(t))
        hits += direction_structure(u, t, estimate_drift_rate(u, t))["structured"]
    # the union bound is conservative: at most alpha in expectation; 300 draws leave room for 3 sd
    assert hits / 300 <= STRUCTURE_ALPHA + 3 * np.sqrt(STRUCTURE_ALPHA / 300)


def test_the_threshold_grows_with_the_scanned_rates_and_shrinks_with_steps():
    t = np.arange(100) * 0.5
    a = direction_structure(np.zeros(100), t)
    b = direction_structure(np.zeros(400), np.arange(400) * 0.5)
    assert a["structured"] and a["statistic"] == 1.0
    assert b["n_rates"] > a["n_rates"] and b["threshold"] < a["threshold"]
    assert not direction_structure([], [])["structured"]
