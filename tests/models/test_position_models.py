"""Models trained on every simulated carrying position: their domain and card.

A small version of experiments/positions-acc.toml (2 subjects x 20 s x 7 positions) is
trained through the CLI: the model's training domain lists every position, its card
names the simulated positions (not "held in the hand"), it reads a new simulated pocket
walk mostly in domain, and it flags a foot-mounted IMU (no carrying position it knows).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.models import load_model, predict_recording
from gaitml.simulate import POSITIONS
from tests.conftest import shared

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def positions_model(tmp_path_factory):
    text = (ROOT / "experiments" / "positions-acc.toml").read_text()
    text = text.replace("subjects = 12", "subjects = 2").replace("duration_s = 150.0", "duration_s = 20.0")
    text = text.replace("cross_validate = true", "cross_validate = false")
    d = tmp_path_factory.mktemp("positions")
    (d / "cfg.toml").write_text(text)
    assert main(["train", str(d / "cfg.toml"), "--out", str(d / "model")]) == 0
    return load_model(d / "model")


def test_the_domain_lists_every_position_and_the_card_names_them(positions_model):
    model = positions_model
    assert model.feature_set == "all52" and model.frame == "phone"
    assert sorted(model.domain.positions) == sorted(POSITIONS)
    assert all(n > 0 for n in model.domain.positions.values())
    card = (model.path / "MODEL.md").read_text()
    assert "front-pocket" in card and "swinging-hand" in card


def test_a_new_simulated_pocket_walk_is_mostly_in_domain(positions_model):
    from gaitml.simulate import sample_subjects, simulate_recording
    from gaitml.simulate.positions import Placement

    subject = sample_subjects(1, 31)[0]
    rec = simulate_recording(
        subject, duration_s=40.0, modes=["walk"], seed=31, placement=Placement.random("front-pocket", np.random.default_rng(31))
    )
    t = predict_recording(positions_model, rec)
    assert t["in_domain"].astype(bool).mean() > 0.8


def test_a_foot_mounted_imu_is_flagged(positions_model):
    from gaitml.io import read_recording

    rec = read_recording(shared("gaitmap-example", "imu_sample.csv.gz"), sensor="left")
    t = predict_recording(positions_model, rec)
    assert len(t) > 20
    assert (~t["in_domain"].astype(bool)).mean() >= 0.8
