"""The joint choice of adaptive's stages 2c and 5a (experiments/scripts/tyrex_steps_joint.py): grid, admissibility,
leave-one-person-out checks and per-step scoring, on made-up tables (no data, fast)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.tyrex_steps_joint import (
    OFF,
    admissible_set,
    choose,
    f1,
    frame,
    lopo,
    params,
    parse_setting,
    settings,
)
from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED

A = ("0.3,0,-1,0", "0.7,0")  # a joint setting: stage 2c at the opt-in, stage 5a at 0.7
B = ("0.5,0.3,-1,10", "0.5,0")


def _grid(delta: dict[str, dict[str, float]]) -> pd.DataFrame:
    """Two recordings per person and motion, count accuracy 0.9 (running 0.97) plus ``delta[person][motion]``."""
    base = {m: 0.97 if m.startswith("Running") else 0.9 for m in SCORED}
    rows = [
        {"recording": f"{p}-{m}-{i}", "motion": m, "person": p, "n": 0, "acc": base[m] + delta.get(p, {}).get(m, 0.0)}
        for p in PEOPLE
        for m in SCORED
        for i in range(2)
    ]
    return pd.DataFrame(rows).assign(hits=np.nan, extras=np.nan, misses=np.nan)


def test_the_grid_holds_all_off_and_maps_to_adaptive_keywords():
    ks = settings()
    assert ks[0] == OFF and len(ks) == len(set(ks)) == 25
    assert params(OFF) == {}
    assert params(A) == {
        "gyro_swing_min_periodicity": 0.3,
        "gyro_swing_half_correlation": 0.0,
        "gyro_swing_acc_correlation": -1.0,
        "gyro_swing_min_bout_steps": 0,
        "octave_swing_min_correlation": 0.7,
        "max_short_bout_interval_cv": 0.0,
    }
    assert parse_setting("0.3,0,-1,0/0.7,0") == A
    with pytest.raises(ValueError, match="2C/5A"):
        parse_setting("0.3/0.7")


def test_admissible_means_no_more_non_gait_steps_than_all_off():
    rates = {OFF: {"gestures": 1.8, "desk": 3.0}, A: {"gestures": 2.4, "desk": 2.0}, B: {"gestures": 1.7, "desk": 3.0}}
    assert admissible_set(rates) == {OFF, B}


def test_a_setting_better_for_everyone_passes_j1_to_j3():
    up = {p: {"Texting": 0.05, "Phoning": 0.02} for p in PEOPLE}
    table, checks, chosen = lopo({OFF: _grid({}), A: _grid(up)}, {OFF, A})
    assert checks == {"J1": True, "J2": True, "J3": True}
    assert chosen == [A, A, A]
    assert "| pooled held out |" in table


def test_an_inadmissible_setting_is_never_chosen():
    up = {p: {"Texting": 0.05} for p in PEOPLE}
    _, checks, chosen = lopo({OFF: _grid({}), A: _grid(up)}, {OFF})
    assert chosen == [OFF, OFF, OFF]
    assert checks["J1"] is False  # all-off everywhere: nothing above today's pooled score


def test_a_setting_that_costs_the_left_out_person_fails():
    # chosen on Jakob and Thibaud (it helps them), it costs Guillaume 0.10 on Texting: J2 and J3 fail
    d = {"Jakob": {"Texting": 0.05}, "Thibaud": {"Texting": 0.05}, "Guillaume": {"Texting": -0.10}}
    table, checks, chosen = lopo({OFF: _grid({}), A: _grid(d)}, {OFF, A})
    assert chosen[0] == A and checks["J2"] is False and checks["J3"] is False
    assert "| Guillaume | 2c 0.3,0,-1,0 / 5a 0.7,0 |" in table


def test_running_below_its_floor_or_below_adfsm_fails_j3():
    g = _grid({})
    g.loc[g["motion"] == "RunningHand", "acc"] = 0.94  # below RUNNING_FLOOR, for all-off and the setting alike
    up = g.copy()
    up.loc[up["motion"] == "Texting", "acc"] += 0.05
    assert lopo({OFF: g, A: up}, {OFF, A})[1]["J3"] is False
    better = _grid({p: {"Texting": 0.05} for p in PEOPLE})
    adfsm = _grid({p: {"Phoning": 0.05} for p in PEOPLE})  # AD-FSM above adaptive on Phoning
    assert lopo({OFF: _grid({}), A: better}, {OFF, A}, adfsm)[1]["J3"] is False


def test_ties_go_to_all_off():
    assert choose({OFF: _grid({}), A: _grid({})}, {OFF, A}) == OFF


def test_frame_scores_the_count_and_the_steps():
    ref = {"t_s": [1.0, 2.0, 3.0, 4.0], "n_steps": 4, "steps_per_event": 1}
    pocket = {"t_s": [1.0, 3.0], "n_steps": 4, "steps_per_event": 2}
    items = [
        {"name": "a", "motion": "Texting", "person": "Jakob", "ref": ref},
        {"name": "b", "motion": "FrontPocket", "person": "Jakob", "ref": pocket},
    ]
    df = frame(items, [np.array([1.1, 1.2, 2.9, 6.0]), np.array([1.0, 2.0, 3.0])])
    a, b = df.iloc[0], df.iloc[1]
    assert (a["n"], a["acc"], a["hits"], a["extras"], a["misses"]) == (4, 1.0, 2, 2, 2)
    assert b["acc"] == pytest.approx(0.75) and np.isnan(b["hits"])  # a stride reference is not matched step by step
    assert f1(df, "Texting") == pytest.approx(0.5)  # the count is right, half the steps are not


def test_a_reference_step_is_missed_when_no_detected_step_is_near_and_the_nearest_window_is_found():
    from experiments.scripts.tyrex_steps_joint import nearest_window, uncovered

    runs = [{"steps": np.array([1.0, 2.1]), "t": np.array([0.0, 5.0])}, {"steps": np.array([9.0]), "t": np.array([10.0])}]
    assert uncovered(np.array([1.2, 2.0, 3.0, 9.5]), runs).tolist() == [False, False, True, True]
    assert uncovered(np.array([1.0]), []).tolist() == [True]
    g, j = nearest_window(runs, 8.0)  # 10.0 (second segment) is nearer than 5.0
    assert g is runs[1] and j == 0
    assert nearest_window([{"t": np.zeros(0)}], 1.0) is None
