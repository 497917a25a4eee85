"""The shipped models for real phones (issue 12): models/positions and models/positions-acc.

They load (data-only format), their training domain lists every simulated carrying
position, they need the sensors their feature set says, and the accelerometer-only one
flags most windows of a foot-mounted IMU (not a carrying position it was trained on).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gaitml.models import load_model, predict_recording
from gaitml.simulate import POSITIONS
from tests.conftest import shared

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(("name", "fset"), [("positions", "all52+gyro"), ("positions-acc", "all52")])
def test_position_model_loads_with_every_position_in_its_domain(name, fset):
    model = load_model(ROOT / "models" / name)
    assert model.feature_set == fset and model.frame == "phone"
    assert sorted(model.domain.positions) == sorted(POSITIONS)
    assert all(n > 0 for n in model.domain.positions.values())
    assert set(model.estimator.classes_) == {"walk", "run", "side_left", "side_right", "backward"}
    size = sum(p.stat().st_size for p in (ROOT / "models" / name).iterdir())
    assert size < 500_000, f"models/{name} is {size} bytes"


def test_position_model_reads_a_simulated_pocket_walk():
    from gaitml.simulate import sample_subjects, simulate_recording
    from gaitml.simulate.positions import Placement

    model = load_model(ROOT / "models" / "positions-acc")
    subject = sample_subjects(1, 31)[0]
    rec = simulate_recording(
        subject, duration_s=40.0, modes=["walk"], seed=31, placement=Placement.random("front-pocket", np.random.default_rng(31))
    )
    t = predict_recording(model, rec)
    assert t["in_domain"].astype(bool).mean() > 0.8


def test_acc_position_model_flags_the_foot_imu():
    from gaitml.io import read_recording

    rec = read_recording(shared("gaitmap-example", "imu_sample.csv.gz"), sensor="left")
    t = predict_recording(load_model(ROOT / "models" / "positions-acc"), rec)
    assert len(t) > 20
    assert (~t["in_domain"].astype(bool)).mean() >= 0.8
