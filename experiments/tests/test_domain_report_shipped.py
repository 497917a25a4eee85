"""experiments.scripts.domain_report --shipped: what the shipped default models say in every simulated carrying position."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.domain_report import positions_pdr_table, shipped_positions_table
from experiments.tests.conftest import ROOT, shared
from gaitml.models import load_model
from gaitml.simulate import POSITIONS

#: the simulator's carrying positions the shipped models are trained in (beside the real tyrex motions)
TRAINED = {"hand-flat", "hand-tilted", "swinging-hand", "front-pocket", "back-pocket"}


def _positions_table():
    models = {name: load_model(ROOT / "models" / name) for name in ("demo", "demo-acc")}
    return shipped_positions_table(models, seed=77, subjects=1, duration_s=40.0)


def test_the_shipped_models_flag_the_bag_they_were_not_trained_on():
    """experiments/reports/default-model.md: models/demo flags the simulated bag (held-out seeds); trained positions are not flagged."""
    t = _positions_table()
    assert len(t) == 2 * len(POSITIONS)
    assert set(t.loc[t["trained as"] == "trained", "data"]) == TRAINED
    demo = t[t["model"] == "demo"].set_index("data")
    assert demo.loc["bag", "flagged out of domain"] >= 0.8
    trained = t[t["trained as"] == "trained"]
    assert (trained["flagged out of domain"] <= 0.3).all(), trained


@pytest.mark.xfail(
    strict=True,
    reason="known gap (default-model.md): in the simulated back pocket models/demo reads over half of the "
    "windows silently wrong: backward read as walk, side steps as run; the models learnt walking from calm real "
    "tyrex walkers, the simulator's walkers are more vigorous (simulator-tyrex.md)",
)
def test_the_shipped_models_answer_most_simulated_windows_in_their_trained_positions():
    t = _positions_table()
    trained = t[t["trained as"] == "trained"]
    np.testing.assert_array_less(trained["silently wrong"], 0.5)


@pytest.mark.xfail(
    strict=True, reason="known gap: the simulated belt moves with the pelvis like the trained back pocket (default-model.md)"
)
def test_the_shipped_demo_flags_the_belt():
    demo = _positions_table().set_index(["model", "data"])
    assert demo.loc[("demo", "belt"), "flagged out of domain"] >= 0.8


def test_steps_the_demo_flags_move_forward_and_model_modes_beat_forward_only_in_the_hand():
    """Out-of-domain steps go along the facing heading (most bag steps); in the hand multi-state PDR beats forward-only."""
    model = load_model(ROOT / "models" / "demo")
    t = positions_pdr_table(model, seeds=(0,), routes=("arc",), out_of_domain=True)
    t = t.set_index("data")
    assert t.loc["bag", "steps moved forward as out of domain"] >= 0.7
    for pos in ("hand-flat", "hand-tilted"):
        assert t.loc[pos, "steps moved forward as out of domain"] < 0.1
        assert t.loc[pos, "multi-state arc end error (% dist)"] < t.loc[pos, "forward-only arc end error (% dist)"]


@pytest.mark.realdata
def test_demo_acc_meets_its_targets_on_real_hand_held_walking():
    """Oxford InHand (16 walks, 3 users): walk >= 90 % of the windows, silently wrong (neither walk
    nor flagged) <= 5 %; measured 98.9 % and 0.8 % (90.5 % and 5.5 % before the simulator's hand
    gain; held out per user: 95.6 % and 2.4 %, experiments/reports/model-domain.md)."""
    from experiments.scripts.domain_report import add_scores, score
    from gaitml.io import read_dataset

    recs = [r for r in read_dataset(shared("oxford-step-counter", "optimisation")) if r.meta.get("position") == "InHand"]
    assert len(recs) == 16
    model = load_model(ROOT / "models" / "demo-acc")
    tot: dict = {}
    for r in recs:
        tot = add_scores(tot, score(model, r))
    assert tot["walk_all"] / tot["windows"] >= 0.90
    assert tot["silent"] / tot["windows"] <= 0.05
