"""A small step-window model trained once for the step-window CLI tests."""

from __future__ import annotations

import pytest

from gaitml.cli import main

STEP_MODEL_CONFIG = """
name = "steps-small"
seed = 5
[data]
source = "simulated"
[data.simulated]
subjects = 3
duration_s = 60.0
[windows]
by = "steps"
detector = "ifsm"
[features]
set = "all52+gyro"
[train]
cross_validate = true
"""


@pytest.fixture(scope="session")
def step_model_dir(tmp_path_factory):
    """A folder holding ``model``: the step-window model (IFSM steps, simulated hand-held phones, no foot position)."""
    d = tmp_path_factory.mktemp("stepmodel")
    (d / "cfg.toml").write_text(STEP_MODEL_CONFIG)
    assert main(["train", str(d / "cfg.toml"), "--out", str(d / "model")]) == 0
    return d
