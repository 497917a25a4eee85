"""Confident or unsure (gaitml.steps.gait_confidence) and what `gaitml steps` says about it."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.simulate import Placement, Subject, simulate_recording
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import CONFIDENT_BOUT_STEPS, CONFIDENT_WINDOW_S, confident_steps, gait_confidence, get_detector, make_step_table
from gaitml.steps._unsure import table_bouts


def _table(t_s: np.ndarray, period_s: float = 0.5):
    fs = 50.0
    pk = np.rint(np.asarray(t_s) * fs).astype(np.int64)
    h = int(period_s * fs / 2)
    return make_step_table(pk - h, pk, pk + h, fs, event="t_peak_s", period_s=np.full(len(pk), period_s))


def test_bouts_split_where_an_interval_exceeds_two_step_periods():
    t = np.r_[1.0, 1.5, 2.0, 2.5, 3.6, 4.1, 10.0]
    assert table_bouts(_table(t)).tolist() == [0, 0, 0, 0, 1, 1, 2]
    assert table_bouts(_table(np.zeros(0))).size == 0


def test_a_bout_of_ten_regular_steps_is_confident_gait():
    walk = gait_confidence(_table(1.0 + 0.5 * np.arange(CONFIDENT_BOUT_STEPS)))
    assert walk["confident_gait"] and walk["longest_bout_steps"] == CONFIDENT_BOUT_STEPS
    assert (walk["n_confident"], walk["n_unsure"]) == (CONFIDENT_BOUT_STEPS, 0)
    # three bursts of six "steps" 5 s apart: as many steps, no bout long enough
    bursts = np.concatenate([s + 0.5 * np.arange(6) for s in (1.0, 10.0, 20.0)])
    g = gait_confidence(_table(bursts))
    assert not g["confident_gait"] and g["n_bouts"] == 3 and g["longest_bout_steps"] == 6
    assert (g["n_confident"], g["n_unsure"]) == (0, 18)
    empty = gait_confidence(_table(np.zeros(0)))
    assert (empty["n_confident"], empty["n_unsure"], empty["confident_gait"]) == (0, 0, False)
    with pytest.raises(ValueError, match="min_bout_steps"):
        gait_confidence(_table(bursts), min_bout_steps=0)
    with pytest.raises(ValueError, match="window_s"):
        gait_confidence(_table(bursts), window_s=-1.0)


def test_short_bouts_near_a_walk_are_confident_far_ones_unsure():
    walk = 100.0 + 0.5 * np.arange(12)  # 100-105.5 s
    near = 100.0 - 0.5 * CONFIDENT_WINDOW_S + 0.5 * np.arange(5)  # a stop-and-go before the walk, within the window
    far = 106.0 + 2 * CONFIDENT_WINDOW_S + 0.5 * np.arange(5)  # a burst long after it
    table = _table(np.sort(np.concatenate([near, walk, far])))
    ok, size = confident_steps(table)
    assert size.tolist() == [5] * 5 + [12] * 12 + [5] * 5
    assert ok.tolist() == [True] * 17 + [False] * 5
    g = gait_confidence(table)
    assert (g["n_confident"], g["n_unsure"], g["confident_gait"]) == (17, 5, True)
    # the whole table at once: one confirmed bout makes every step confident
    assert gait_confidence(table, window_s=np.inf)["n_unsure"] == 0
    # step order in the table does not matter
    shuffled = table.iloc[np.random.default_rng(0).permutation(len(table))]
    assert confident_steps(shuffled)[0].sum() == 17


def _cli_json(tmp_path, rec, capsys):
    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    path = write_gaitml_csv(rec, tmp_path / f"{rec.name}.csv")
    assert main(["steps", str(path), "--json"]) == 0
    cap = capsys.readouterr()
    assert main(["steps", str(path)]) == 0
    text = capsys.readouterr()
    return json.loads(cap.out), cap.err, text.out, text.err


def test_cli_says_the_steps_of_gesturing_hands_are_unsure(tmp_path, capsys):
    n_with_steps = 0
    # the gait check leaves out most gesture bursts (on seeds 0-3 all of them): a phone handled at a desk keeps a few
    for kind, seed in [("gestures", s) for s in range(4)] + [("desk", s) for s in range(4)]:
        obj, err, text, text_err = _cli_json(tmp_path, simulate_nongait(kind, duration_s=120, seed=seed), capsys)
        assert obj["n_confident"] + obj["n_unsure"] == obj["n_steps"]
        assert obj["gait_confidence"]["min_bout_steps"] == CONFIDENT_BOUT_STEPS
        if obj["n_steps"]:
            n_with_steps += 1
            # most (here: all) of a gesturing hand's steps are unsure, nothing is dropped, one note says so
            assert obj["n_unsure"] > obj["n_steps"] / 2
            assert sum(not st["confident"] for st in obj["steps"]) == obj["n_unsure"]
            assert err.count("no confident gait found") == 1 and text_err.count("no confident gait found") == 1
            assert f"{obj['n_steps']} steps, {obj['n_confident']} confident, {obj['n_unsure']} unsure" in text
    assert n_with_steps >= 1, "no seed gave steps: the test did not exercise the note"


@pytest.mark.parametrize("position", ["hand-flat", "front-pocket", "back-pocket"])
def test_cli_says_a_walk_is_confident_gait(tmp_path, capsys, position):
    rng = np.random.default_rng(11)
    placement = None if position.startswith("hand") else Placement.random(position, rng)
    rec = simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=60, seed=11, placement=placement)
    obj, err, text, _ = _cli_json(tmp_path, rec, capsys)
    assert obj["n_steps"] > 0.9 * rec.reference["n_steps_true"]
    assert obj["n_confident"] == obj["n_steps"] and obj["n_unsure"] == 0
    assert all(st["confident"] for st in obj["steps"])
    assert "no confident gait found" not in err
    assert f"{obj['n_steps']} steps, {obj['n_steps']} confident, 0 unsure" in text


def test_detectors_without_a_confidence_get_no_verdict(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    rec = simulate_nongait("gestures", duration_s=60, seed=1)
    assert "confidence" not in get_detector("single-peak").detect(rec).steps_.columns
    path = write_gaitml_csv(rec, tmp_path / "g.csv")
    assert main(["steps", str(path), "--detector", "single-peak", "--json"]) == 0
    cap = capsys.readouterr()
    assert "n_unsure" not in json.loads(cap.out) and "no confident gait" not in cap.err


def test_a_walk_too_short_to_confirm_says_so_and_the_written_table_carries_the_verdict(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    rng = np.random.default_rng(11)
    rec = simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=4, seed=11)
    obj, err, _, _ = _cli_json(tmp_path, rec, capsys)
    assert 0 < obj["n_steps"] < CONFIDENT_BOUT_STEPS and obj["n_unsure"] == obj["n_steps"]
    assert "too short to confirm gait" in err and "handled" not in err
    path = write_gaitml_csv(rec, tmp_path / "short.csv")
    out = tmp_path / "steps.csv"
    assert main(["steps", str(path), "--out", str(out)]) == 0
    capsys.readouterr()
    table = pd.read_csv(out)
    assert "confident" in table.columns and len(table) == obj["n_steps"] and not table["confident"].any()


def test_ten_irregular_steps_in_a_short_recording_are_not_called_too_short():
    from gaitml.commands.steps import _unsure_note

    sure = {
        "n_confident": 0,
        "n_unsure": 13,
        "min_bout_steps": CONFIDENT_BOUT_STEPS,
        "window_s": 60.0,
        "longest_bout_steps": 6,
        "n_bouts": 3,
    }
    assert "too short" not in _unsure_note(sure, 7.0, 0.5)
    assert "too short" in _unsure_note({**sure, "n_unsure": 8, "n_bouts": 1, "longest_bout_steps": 8}, 4.0, 0.5)
