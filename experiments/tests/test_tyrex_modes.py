"""The tyrex modes study's own pieces: the speed rule and the window scores, on known answers."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.tyrex_modes import RECIPES, moving_labels, score_windows, summarise


def test_moving_labels_follow_the_body_speed_and_leave_the_uncaptured_out():
    """Stand 10 s, walk 20 s at 1 m/s (arm swing of 0.3 m at 1 Hz on top), stand 10 s: only the walk is moving."""
    tt = np.arange(0, 40, 1 / 60)
    x = np.clip(tt - 10, 0, 20)
    swing = 0.3 * np.sin(2 * np.pi * 1.0 * tt) * ((tt > 10) & (tt < 30))
    xy = np.column_stack([x + swing, np.zeros_like(tt)])
    t = np.arange(-2, 42, 1 / 50)
    lab = moving_labels(t, tt, xy, "walk")
    assert set(lab[t < 0]) == {"unlabelled"} and set(lab[t > 40]) == {"unlabelled"}
    assert set(lab[(t > 13) & (t < 27)]) == {"walk"}
    assert set(lab[((t > 1) & (t < 7)) | ((t > 33) & (t < 39))]) == {"still"}
    walk_s = np.sum(lab == "walk") / 50
    assert walk_s == pytest.approx(20, abs=2)


def test_a_phone_swinging_in_a_still_hand_is_not_moving():
    """The 0.5 Hz low-pass removes a 1 Hz swing of 0.3 m: a person standing still is still."""
    tt = np.arange(0, 30, 1 / 60)
    xy = np.column_stack([0.3 * np.sin(2 * np.pi * tt), np.zeros_like(tt)])
    lab = moving_labels(np.arange(5, 25, 0.02), tt, xy, "walk")
    assert set(lab) == {"still"}


def test_score_windows_splits_right_flagged_and_silently_wrong():
    pred = pd.DataFrame(
        {
            "label": ["walk", "walk", "walk", "walk", "still", "walk", "walk"],
            "label_fraction": [1.0, 1.0, 1.0, 1.0, 1.0, 0.4, 1.0],
            "mode": ["walk", "backward", "walk", "run", "walk", "walk", "still"],
            "in_domain": np.array([True, True, False, True, True, True, True], dtype=object),
        }
    )
    s = score_windows(pred, "walk")
    # the moving window the still gate answered 'still' is silently wrong, and counted apart
    assert s == {"n": 5, "right": 1, "flagged": 1, "wrong": 3, "as_still": 1}


def test_summarise_pools_windows_and_gives_the_spread_over_people():
    t = pd.DataFrame(
        {
            "subject": ["A", "B"],
            "motion": ["Texting", "Texting"],
            "n": [10, 30],
            "right": [10, 15],
            "flagged": [0, 15],
            "wrong": [0, 0],
            "as_still": [0, 0],
            "n_still": [4, 0],
            "still_flagged": [1, 0],
            "still_moded": [2, 0],
        }
    )
    row = summarise(t).iloc[0]
    assert row["right"] == pytest.approx(25 / 40)
    assert row["standing windows"] == 4 and row["standing read as a mode"] == pytest.approx(0.5)
    assert row["right per left-out"] == "0.50-1.00"


def test_every_recipe_keeps_side_steps_and_backward_from_the_simulator():
    for name, (sim_modes, weight) in RECIPES.items():
        assert {"side_left", "side_right", "backward"} <= set(sim_modes)
        assert weight >= 1 or name == "sim"


def test_recipe_b_keeps_only_the_simulated_side_steps_and_backward():
    from experiments.scripts.tyrex_modes import keep_modes
    from gaitml.recording import Recording

    n = 8
    labels = np.array(["walk", "run", "side_left", "side_right", "backward", "walk", "backward", "run"], dtype=object)
    acc = np.tile([0.0, 0.0, 9.81], (n, 1))
    rec = Recording.from_arrays(acc, 50.0, labels=labels)
    kept = keep_modes(rec, RECIPES["b"][0]).labels.astype(str)
    assert list(kept) == ["unlabelled", "unlabelled", "side_left", "side_right", "backward", "unlabelled", "backward", "unlabelled"]


def test_the_walking_rule_changes_what_is_scored_not_the_answers(monkeypatch):
    """window_table scores over ``score_recording``'s labels when an item has one: the same answers, another denominator."""
    import gaitml.models
    from experiments.scripts.tyrex_ar_moving import NOT_WALKING
    from experiments.scripts.tyrex_modes import window_table
    from gaitml.features import make_windows
    from gaitml.recording import Recording

    fs = 50.0
    n = int(30 * fs)
    rng = np.random.default_rng(0)
    acc = rng.normal(0, 0.1, (n, 3)) + [0, 0, 9.81]
    speed_lab = np.array(["walk"] * n, dtype=object)
    walk_lab = speed_lab.copy()
    walk_lab[: n // 2] = NOT_WALKING  # the first 15 s: moving by speed, not walking
    rec = Recording(acc=acc, sampling_rate_hz=fs, labels=speed_lab, meta={"id": "x"}, check_units=False)

    def fake_predict(model, recording, **kw):  # answers 'still' in the first half, 'walk' after, whatever the labels
        w = make_windows(recording, 1.5, 0.5, min_label_fraction=0.0).reset_index(drop=True)
        w["mode"] = np.where(w["end"] <= n // 2, "still", "walk")
        w["in_domain"] = np.array([True] * len(w), dtype=object)
        return w

    monkeypatch.setattr(gaitml.models, "predict_recording", fake_predict)
    item = {"subject": "A", "phone": "P", "motion": "AR", "mode": "walk", "recording": rec}
    by_speed = window_table(None, [item]).iloc[0]
    by_walking = window_table(None, [{**item, "score_recording": rec.replace(labels=walk_lab, check_units=False)}]).iloc[0]
    assert by_walking["n"] < 0.6 * by_speed["n"]  # the not-walking half left the denominator
    assert by_speed["as_still"] > 0.4 * by_speed["n"]  # over the speed rule the first half is silently 'still'
    assert by_walking["as_still"] <= 1  # at most the window straddling the change
    assert abs(by_walking["right"] - by_speed["right"]) <= 1  # the same answers: the right windows stay right
    # the windows that left are counted apart, with what they were answered ('still' here)
    assert by_walking["n_notwalk"] >= by_speed["n"] - by_walking["n"] - 1 and by_speed["n_notwalk"] == 0
    assert by_walking["notwalk_still"] >= by_walking["n_notwalk"] - 1 and by_walking["notwalk_mode"] <= 1


def test_at_rate_gives_the_recording_as_a_slower_phone_records_it_with_its_labels():
    from experiments.scripts.tyrex_modes import at_rate
    from gaitml.models import resample_recording
    from gaitml.recording import Recording

    fs, n = 50.0, 500
    lab = np.where(np.arange(n) < 250, "still", "walk").astype(object)
    acc = np.tile([0.0, 0.0, 9.81], (n, 1)) + np.outer(np.sin(np.arange(n) / 3.0), [1.0, 0.0, 0.0])
    rec = Recording(acc=acc, sampling_rate_hz=fs, labels=lab)
    (it,) = at_rate([{"recording": rec, "score_recording": rec, "mode": "walk"}], 20.0)
    for key in ("recording", "score_recording"):
        low = it[key]
        assert low.sampling_rate_hz == 20.0
        np.testing.assert_array_equal(low.acc, resample_recording(rec, 20.0).acc)
        # the label of the nearest original sample: the switch stays at 5 s
        t_switch = low.t_s[np.argmax(low.labels.astype(str) == "walk")]
        assert abs(t_switch - 5.0) <= 1 / 20.0
    assert at_rate([{"recording": rec}], 50.0)[0]["recording"] is rec  # at its own rate: unchanged
