"""adaptive's walking-episode bout rule (stage 5b): a short regular bout between two walks is walking.

The detector runs it by default where the gait check reads a gyroscope, and adds its steps after the check (round 3,
experiments/reports/tyrex-steps.md); :func:`adaptive_steps` alone keeps it off unless asked (rounds 1-2's form)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

from gaitml.recording import Recording
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import confident_steps, get_detector
from gaitml.steps.adaptive import _episode_keep, adaptive_steps, bout_edge_keep, episode_steps_after_check

#: stage 5b at three step periods, interval CV 0.1, no edge match (a setting of the lab's grid, experiments/reports/tyrex-steps.md)
ON = {"episode_gap_ratio": 3.0, "max_bout_interval_cv": 0.1, "edge_interval_match": False}
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


def test_adaptive_steps_alone_keeps_the_episode_rule_off_by_default():
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


def _phone(mag: np.ndarray, fs: float, gyro: bool, seed: int = 0) -> Recording:
    """|acc| along z and, with ``gyro``, a walker's swing: about x once per stride (two steps), 1.5 rad/s."""
    rng = np.random.default_rng(seed)
    n = len(mag)
    acc = np.column_stack([np.zeros(n), np.zeros(n), mag]) + rng.normal(0, 0.02, (n, 3))
    if not gyro:
        return Recording.from_arrays(acc, fs)
    t = np.arange(n) / fs
    gyr = np.column_stack([1.5 * np.sin(np.pi * t / STEP_S), np.zeros(n), np.zeros(n)]) + rng.normal(0, 0.01, (n, 3))
    return Recording.from_arrays(acc, fs, gyr=gyr)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_detector_counts_a_short_regular_bout_between_two_walks_with_a_gyroscope(seed):
    mag, fs, n_true = _walk_stop_walk(seed)
    rec = _phone(mag, fs, gyro=True, seed=seed)
    det = get_detector("adaptive").detect(rec)
    off = get_detector("adaptive", episode_gap_ratio=0.0).detect(rec).steps_
    assert len(off) <= n_true - 3  # without stage 5b the three steps between the walks are dropped
    assert abs(len(det.steps_) - n_true) <= 1
    assert det.steps_.attrs["episode"]["ran"] and det.steps_.attrs["episode"]["added"] >= 3
    assert det.steps_["t_peak_s"].is_monotonic_increasing


def test_without_a_gyroscope_the_step_table_is_unchanged():
    mag, fs, n_true = _walk_stop_walk(0)
    rec = _phone(mag, fs, gyro=False)
    st = get_detector("adaptive").detect(rec).steps_
    off = get_detector("adaptive", episode_gap_ratio=0.0).detect(rec).steps_
    pd.testing.assert_frame_equal(st, off)
    assert len(st) <= n_true - 3
    assert st.attrs["episode"] == {"ran": False, "added": 0, "withheld": 0}
    # nor with the gait check off: the stage reads the check's verdict
    rec_g = _phone(mag, fs, gyro=True)
    a = get_detector("adaptive", gait_check=False).detect(rec_g).steps_
    b = get_detector("adaptive", gait_check=False, episode_gap_ratio=0.0).detect(rec_g).steps_
    pd.testing.assert_frame_equal(a, b)


def test_asked_for_explicitly_without_a_gyroscope_one_warning_says_it_did_not_run():
    mag, fs, _ = _walk_stop_walk(0)
    rec = _phone(mag, fs, gyro=False)
    with pytest.warns(UserWarning, match="walking-episode stage") as w:
        get_detector("adaptive", **ON).detect(rec)
    assert len([x for x in w if "walking-episode" in str(x.message)]) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        get_detector("adaptive").detect(rec)  # at the defaults: no warning, attrs['episode'] says it did not run


def test_episode_steps_join_only_beside_walking_that_survived_the_gait_check():
    # today's steps: walking bout 0 (episode 0), walking bout 3 (episode 1); stage 5b adds bout 1 (episode 0),
    # bout 4 (episode 1) and an edge step of bout 3
    today = {
        "peak": np.array([0, 10, 20, 100, 110]),
        "bout": np.array([0, 0, 0, 3, 3]),
        "episode": np.array([0, 0, 0, 1, 1]),
        "walking": np.ones(5, dtype=bool),
    }
    added = {
        "peak": np.array([40, 50, 90, 140]),
        "bout": np.array([1, 1, 3, 4]),
        "episode": np.array([0, 0, 1, 1]),
        "walking": np.array([False, False, True, False]),
    }
    assert episode_steps_after_check(today, added, today["peak"]).all()
    # the gait check rejected bout 3: its edge step and the bout rescued beside it go too, bout 1 stays
    assert episode_steps_after_check(today, added, np.array([0, 10, 20])).tolist() == [True, True, False, False]
    assert not episode_steps_after_check(today, added, np.zeros(0, dtype=np.int64)).any()


@pytest.mark.parametrize("seed", [100, 101, 112])
def test_gestures_give_no_confident_steps_with_the_episode_rule(seed):
    rec = simulate_nongait("gestures", duration_s=120, seed=seed)
    st = get_detector("adaptive").detect(rec).steps_
    assert int(np.sum(confident_steps(st)[0])) == 0
    # and no step more than without the stage: what it adds joins only beside walking the gait check kept
    assert len(st) <= len(get_detector("adaptive", episode_gap_ratio=0.0).detect(rec).steps_)


def test_run_before_the_gait_check_a_rescued_gesture_burst_outlives_its_rejected_neighbour():
    # held-out gestures seed 112 (the lab's round 2): before the check the rule adds four steps the check lets through
    rec = simulate_nongait("gestures", duration_s=120, seed=112)
    off = len(get_detector("adaptive", episode_gap_ratio=0.0).detect(rec).steps_)
    before = get_detector("adaptive", **ON, episode_before_gait_check=True).detect(rec).steps_
    after = get_detector("adaptive", **ON).detect(rec).steps_
    assert len(before) > off
    assert len(after) == off
