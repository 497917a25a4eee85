"""adaptive's walking-episode bout rule (stage 5b, opt-in): a short regular bout between two walks is walking."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import confident_steps, get_detector
from gaitml.steps.adaptive import _episode_keep, adaptive_steps, bout_edge_keep

#: stage 5b on (three step periods, interval CV 0.1: the lab's round-2 grid, experiments/reports/tyrex-steps.md)
ON = {"episode_gap_ratio": 3.0, "max_bout_interval_cv": 0.1}
STEP_S = 0.55


def _walk_stop_walk(seed: int, middle: int = 3, far_s: float = 0.0, fs: float = 50.0):
    """|acc| of 30 steps, a pause of 2.5 step periods (one step missed, a hesitation), ``middle`` regular steps, the
    same pause and 30 more steps; ``far_s`` seconds more on both sides of the middle bout put it away from any walk."""
    rng = np.random.default_rng(seed)
    a = 5.0 + np.arange(30) * STEP_S
    b = a[-1] + 2.5 * STEP_S + far_s + np.arange(middle) * STEP_S
    c = b[-1] + 2.5 * STEP_S + far_s + np.arange(30) * STEP_S
    steps = np.r_[a, b, c] + rng.normal(0, 0.005, 60 + middle)
    n = int((steps[-1] + 5) * fs)
    t = np.arange(n) / fs
    mag = 9.81 + rng.normal(0, 0.05, n)
    for s in steps:
        mag += 2.0 * np.exp(-0.5 * ((t - s) / 0.06) ** 2)
    return mag, fs, len(steps)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_short_regular_bout_between_two_walks_is_counted(seed):
    mag, fs, n_true = _walk_stop_walk(seed)
    off = len(adaptive_steps(mag, fs)["peak"])
    on = len(adaptive_steps(mag, fs, **ON)["peak"])
    assert off <= n_true - 3  # today's minimum-bout rule drops the three steps between the walks
    assert abs(on - n_true) <= 1
    assert on >= off + 3


def test_a_short_regular_bout_away_from_walking_is_still_dropped():
    mag, fs, n_true = _walk_stop_walk(0, far_s=30.0)
    on = adaptive_steps(mag, fs, **ON)
    t = on["peak"] / fs
    assert len(on["peak"]) <= n_true - 3
    # nothing counted in the 30 s either side of the middle bout's three steps
    assert not np.any((t > 23.0) & (t < 84.0))


def test_the_episode_rule_is_off_by_default():
    mag, fs, _ = _walk_stop_walk(1)
    assert np.array_equal(adaptive_steps(mag, fs)["peak"], adaptive_steps(mag, fs, episode_gap_ratio=0.0)["peak"])


def test_episode_keep_needs_regular_intervals_and_a_walking_neighbour():
    T = np.full(14, 10.0)
    # bout 0: ten steps (walking), bout 1: three steps 25 samples after it, regular or not
    pk_reg = np.r_[np.arange(10) * 10, 115, 125, 135, 300]
    pk_irr = np.r_[np.arange(10) * 10, 115, 122, 137, 300]
    bout = np.r_[np.zeros(10, dtype=np.int64), 1, 1, 1, 2]
    ok = np.ones(14, dtype=bool)
    alone = np.array([True, False, False])
    walking = np.array([True, False, False])
    assert _episode_keep(pk_reg, T, bout, ok, alone, walking, 3, 3.0, 0.1).tolist() == [False, True, False]
    assert _episode_keep(pk_irr, T, bout, ok, alone, walking, 3, 3.0, 0.1).tolist() == [False, False, False]
    # no walking bout in the episode: nothing kept
    assert not _episode_keep(pk_reg, T, bout, ok, alone, np.zeros(3, dtype=bool), 3, 3.0, 0.1).any()
    # a gap over gap_ratio periods: another episode
    assert not _episode_keep(pk_reg, T, bout, ok, alone, walking, 3, 2.0, 0.1).any()


def test_bout_edge_keep_keeps_a_weak_edge_step_at_the_bouts_rhythm_when_asked():
    bout = np.zeros(12, dtype=np.int64)
    conf = np.r_[0.1, np.full(11, 0.8)]
    pk = np.arange(12) * 10
    assert not bout_edge_keep(bout, conf, 0.5)[0]
    assert bout_edge_keep(bout, conf, 0.5, pk, 0.1)[0]
    assert not bout_edge_keep(bout, conf, 0.5, pk, 0.1, min_match_steps=20)[0]  # only in bouts of 20 steps
    off_rhythm = pk.copy()
    off_rhythm[0] = -6  # its interval is 1.6 times the bout's
    assert not bout_edge_keep(bout, conf, 0.5, off_rhythm, 0.1)[0]


@pytest.mark.parametrize("seed", [100, 101, 112])
def test_gestures_give_no_confident_steps_with_the_episode_rule_on(seed):
    # seed 112: the rule adds four steps there (the lab's held-out check); none of them is confident gait
    rec = simulate_nongait("gestures", duration_s=120, seed=seed)
    st = get_detector("adaptive", **ON).detect(rec).steps_
    assert int(np.sum(confident_steps(st)[0])) == 0
