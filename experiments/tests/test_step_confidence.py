"""experiments.scripts.step_confidence: the rule that chooses an "unsure" threshold and the tables that score it."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.step_confidence import (
    MAX_UNSURE,
    bout_sizes,
    choose_threshold,
    choose_window,
    confident_within,
    main,
    per_recording,
    simulated_steps,
    tradeoff,
)
from gaitml.errors import InputError


def test_choose_threshold_keeps_every_group_within_the_allowed_share():
    rng = np.random.default_rng(0)
    groups = {"a": rng.uniform(0.2, 1.0, 5000), "b": rng.uniform(0.05, 1.0, 5000)}
    t = choose_threshold(groups)
    # the binding group is b: its 2 % quantile is 0.05 + 0.02 * 0.95 = 0.069
    assert all(np.mean(c < t) <= MAX_UNSURE for c in groups.values())
    assert np.mean(groups["b"] < t + 0.01) > MAX_UNSURE  # the next grid step would break the rule
    assert 0.06 <= t <= 0.07


def test_bout_sizes_split_at_two_step_periods():
    t = np.array([0.0, 0.5, 1.0, 1.5, 5.0, 5.5, 6.0, 20.0])
    assert bout_sizes(t, np.full(len(t), 0.5)).tolist() == [4, 4, 4, 4, 3, 3, 3, 1]
    assert bout_sizes(np.zeros(0), np.zeros(0)).tolist() == []


def _toy():
    recs = pd.DataFrame(
        {
            "recording": ["w", "g"],
            "source": ["tyrex", "nongait"],
            "group": ["Texting", "gestures"],
            "person": ["Jakob", "held-out"],
            "minutes": [2.0, 2.0],
        }
    )
    steps = pd.DataFrame(
        {
            "recording": ["w"] * 10 + ["g"] * 4,
            "confidence": [0.9] * 8 + [0.2, 0.3] + [0.1, 0.1, 0.1, 0.6],
            "bout": [10] * 10 + [4] * 4,
            "matched": [True] * 10 + [False] * 4,
        }
    ).merge(recs, on="recording")
    return steps, recs


def test_per_recording_flags_mostly_unsure_recordings():
    steps, recs = _toy()
    rr = per_recording(steps, recs, 0.5).set_index("recording")
    assert rr.loc["w", "n_confident"] == 8 and not rr.loc["w", "mostly_unsure"]
    assert rr.loc["g", "n_confident"] == 1 and rr.loc["g", "mostly_unsure"]
    assert rr.loc["g", "confident_per_min"] == pytest.approx(0.5)


def test_tradeoff_counts_unsure_real_steps_and_confident_nongait_steps():
    rows = []
    recs = []
    # each real group: 8 steps at 0.9 in a bout of 8, 2 steps at 0.2 in a bout of 2
    real = [
        ("tyrex", m, "Jakob") for m in ("Texting", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket", "AR")
    ]
    real += [("oxford", "InHand", "Jamie"), ("slow-walk", "hand-flat", "selection"), ("slow-walk", "hand-flat", "held-out")]
    for i, (source, group, person) in enumerate(real):
        recs.append({"recording": f"r{i}", "source": source, "group": group, "person": person, "minutes": 1.0})
        rows += [{"recording": f"r{i}", "confidence": 0.9, "bout": 8}] * 8 + [{"recording": f"r{i}", "confidence": 0.2, "bout": 2}] * 2
    # each non-gait recording (2 minutes): one confident step (0.6) and three unsure ones, all in a bout of 4
    for split in ("selection", "held-out"):
        for kind in ("gestures", "desk"):
            name = f"{kind}-{split}"
            recs.append({"recording": name, "source": "nongait", "group": kind, "person": split, "minutes": 2.0})
            rows += [{"recording": name, "confidence": c, "bout": 4} for c in (0.6, 0.1, 0.1, 0.1)]
    recs = pd.DataFrame(recs)
    steps = pd.DataFrame(rows).assign(matched=True).merge(recs, on="recording")
    out = tradeoff(steps, recs, [(0.5, 0), (0.0, 5), (0.05, 0)]).set_index(["threshold", "min bout"])
    assert out.loc[(0.5, 0), "tyrex Texting %"] == pytest.approx(20.0)
    assert out.loc[(0.5, 0), "gestures held-out /min"] == pytest.approx(0.5)
    # a bout of at least 5 steps: the walkers' 2-step bouts and every non-gait bout (4) are unsure
    assert out.loc[(0.0, 5), "oxford %"] == pytest.approx(20.0)
    assert out.loc[(0.0, 5), "desk selection /min"] == 0.0
    assert out.loc[(0.05, 0), "slow held-out worst position %"] == 0.0
    assert out.loc[(0.05, 0), "desk held-out /min"] == pytest.approx(2.0)


def test_simulated_steps_one_seed():
    steps, recs = simulated_steps(seeds=(0,))
    steps = steps.merge(recs, on="recording")
    assert set(recs.group) == {"hand-flat", "hand-tilted", "front-pocket", "gestures", "desk"}
    walk = steps[steps.source == "slow-walk"]
    assert len(walk) > 100 and walk.matched.mean() > 0.9  # adaptive finds the slow walker's steps
    assert (steps.confidence.between(0.0, 1.0)).all()
    assert (steps.bout >= 1).all()


def test_main_needs_the_data(tmp_path):
    with pytest.raises(InputError, match="--data"):
        main(["--data", str(tmp_path), "--cache", ""])


def test_confident_within_and_bout_sizes_are_the_librarys_rule():
    from gaitml.simulate import Subject, simulate_recording
    from gaitml.simulate.nongait import simulate_nongait
    from gaitml.steps import CONFIDENT_WINDOW_S, confident_steps, get_detector

    walk_rec = simulate_recording(Subject.random(np.random.default_rng(2)), modes=["walk"], duration_s=30, seed=2)
    walk = get_detector("adaptive").detect(walk_rec).steps_
    gest = get_detector("adaptive").detect(simulate_nongait("gestures", duration_s=120, seed=1)).steps_
    # the gestures start 100 s after the walk: the window spares their first minute, not the rest
    both = pd.concat([walk, gest.assign(t_peak_s=gest.t_peak_s + 130.0)], ignore_index=True)
    both.attrs = walk.attrs
    ok_lib, size_lib = confident_steps(both)
    assert ok_lib[: len(walk)].all()
    t = both["t_peak_s"].to_numpy()
    size_lab = bout_sizes(t, both["period_s"].to_numpy())
    assert (size_lab == size_lib).all()
    assert (confident_within(t, size_lab, CONFIDENT_WINDOW_S) == ok_lib).all()


def test_choose_window_takes_the_shortest_that_spares_every_selection_group():
    # person A's 12-step bout and, 15 s later, a 4-step bout; person B: one long bout. Slow walkers: one long bout.
    rows = [("A", "tyrex", "Texting", 0.5 * i, 12) for i in range(12)] + [("A", "tyrex", "Texting", 21.0 + 0.5 * i, 4) for i in range(4)]
    rows += [("B", "tyrex", "Texting", 0.5 * i, 100) for i in range(100)]
    rows += [("selection", "slow-walk", "hand-flat", 0.5 * i, 50) for i in range(50)]
    steps = pd.DataFrame(rows, columns=["person", "source", "group", "t", "bout"])
    steps["recording"] = steps.person + steps.group
    # A's short bout is 4 of 16 steps (25 %): spared from a window of 20 s (15.5 s from the walk's last step) on
    assert choose_window(steps, ["A", "B"]) == 20.0
    # without A, nothing needs a window
    assert choose_window(steps, ["B"]) == 0.0
