"""experiments/scripts/tyrex_hde.py scores the library's guard (gaitml.pdr.hde, no twin code): its ``hde guarded``
variant is ``hde_heading``'s default, its ``hde`` variant HDE with the guard off; on synthetic per-step loop walks
(no dominant directions) the two differ and the guarded one keeps the gyro heading, on a corridor they agree.
The guard's own tests are the library's (tests/pdr/test_hde_guard.py)."""

from __future__ import annotations

import numpy as np

from experiments.scripts.tyrex_hde import guarded_hde, heading_variants
from gaitml.pdr.attitude import wrap_angle
from gaitml.pdr.hde import hde_heading


def _loop_walk(seed: int, n: int = 220, step_s: float = 0.55):
    """Steps round a 5 m room: the heading turns 0.3-0.6 rad/s (a loop every 10-20 s), varying, plus step noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * step_s
    turn = 0.45 + 0.15 * np.sin(2 * np.pi * t / rng.uniform(20, 40) + rng.uniform(0, 2 * np.pi))
    truth = np.cumsum(turn * step_s) + rng.uniform(-np.pi, np.pi)
    return t, truth + rng.normal(0, np.deg2rad(3), n)


def _variants(t, raw):
    return heading_variants({"gyro_h": raw, "dur": np.full(len(t), float(t[1] - t[0])), "t_step": t})


def test_variants_are_the_librarys_hde_with_and_without_its_guard():
    held = 0
    for seed in range(10):
        t, raw = _loop_walk(seed)
        v = _variants(t, raw)
        dur = np.full(len(t), 0.55)
        np.testing.assert_array_equal(v["hde guarded"], hde_heading(raw, dur, t)[0])
        np.testing.assert_array_equal(v["hde"], hde_heading(raw, dur, t, structure_alpha=None)[0])
        h, check = guarded_hde(raw, dur, t)
        np.testing.assert_array_equal(h, v["hde guarded"])
        if not check["hde_applied"]:
            held += 1
            np.testing.assert_array_equal(h, wrap_angle(raw))
            assert not np.array_equal(v["hde"], v["hde guarded"])
    assert held >= 8


def test_on_a_corridor_the_guarded_and_unguarded_variants_agree():
    n = 400
    t = np.arange(n) * 0.5
    truth = np.repeat(np.deg2rad([0.0, 90.0, 180.0, 270.0]), n // 4)
    raw = wrap_angle(truth + 0.02 * t + np.random.default_rng(1).normal(0, np.deg2rad(2), n))
    v = _variants(t, raw)
    np.testing.assert_array_equal(v["hde guarded"], v["hde"])
    assert np.degrees(np.median(np.abs(wrap_angle(v["hde guarded"] - truth)))) < 3.0
