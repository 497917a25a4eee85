"""The steps-real experiment: committed config, validation, output tables."""

import json
from pathlib import Path

import pandas as pd
import pytest

from gaitml.errors import ConfigError
from gaitml.experiments.steps_real import load_steps_config, run_steps_real

ROOT = Path(__file__).resolve().parents[2]


def test_committed_config_builds():
    cfg = load_steps_config(ROOT / "experiments" / "steps-real.toml")
    assert "adaptive" in cfg["detectors"] and cfg["tolerance_s"] == 0.25
    assert cfg["data_dir"].name == "data"


@pytest.mark.parametrize(
    "text, match",
    [
        ("bogus = 1", "unknown key"),
        ('detectors = ["nope"]', "unknown name"),
        ("tolerance_s = -1", "positive"),
        ('[data]\nsets = ["x"]', "data.sets"),
    ],
)
def test_bad_config(tmp_path, text, match):
    p = tmp_path / "c.toml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=match):
        load_steps_config(p)


def test_run_writes_tables(ifsm_recs, tmp_path):
    out = tmp_path / "run"
    summary = run_steps_real(out, data_dir=tmp_path, detectors=["single-peak", "ifsm"], recordings=ifsm_recs)
    table = pd.read_csv(out / "per_recording.csv")
    assert len(table) == 4 and set(table["detector"]) == {"single-peak", "ifsm"}
    assert summary["ifsm"]["single-peak"]["acceleration_flat_holding_1"]["n_detected"] == 284
    assert summary["ifsm_first10_period_mad_s"] <= 0.03
    assert json.loads((out / "summary.json").read_text())["tolerance_s"] == 0.25
    assert "| ifsm | 283 | 319 | 284 | 319 |" in (out / "report.md").read_text()
