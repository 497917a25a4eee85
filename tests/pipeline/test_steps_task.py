"""The step-detector experiment (``task = "steps"``): committed config, validation, output tables, `gaitml evaluate`."""

import json
from pathlib import Path

import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.errors import ConfigError
from gaitml.io import read_recording
from gaitml.pipeline import load_config, parse_config
from gaitml.pipeline.steps_real import evaluate_steps_config, run_steps_real
from gaitml.steps import detector_names, get_detector
from tests.conftest import shared

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def ifsm_recs():
    from gaitml.io import read_recording

    return [read_recording(shared("ifsm-flat-phone", f"acceleration_flat_holding_{i}.xlsx")) for i in (1, 2)]


def test_committed_config_builds():
    cfg = load_config(ROOT / "experiments" / "steps-real.toml", check_paths=False)
    assert cfg.task == "steps"
    assert "adaptive" in cfg["steps"]["detectors"] and cfg["steps"]["tolerance_s"] == 0.25
    assert cfg.data_path.name == "data"


def test_defaults_come_from_the_registry(tmp_path):
    cfg = parse_config({"name": "s", "task": "steps", "data": {"path": str(tmp_path)}})
    assert cfg["steps"]["detectors"] == list(detector_names())
    assert cfg["data"]["sets"] == ["ifsm-flat-phone", "oxford-step-counter"]


@pytest.mark.parametrize(
    "raw, match",
    [
        ({"bogus": 1}, "unknown key bogus"),
        ({"steps": {"detectors": ["nope"]}}, r"steps.detectors has 'nope', which is not allowed; allowed: 'single-peak'"),
        ({"steps": {"tolerance_s": -1}}, r"steps.tolerance_s = -1 must be > 0"),
        ({"data": {"sets": ["x"]}}, r"data.sets has 'x', which is not allowed"),
        ({"windows": {"length_s": 1.0}}, "unknown key windows"),
        ({"sweep": {"steps.tolerance_s": [0.1, 0.2]}}, r"\[sweep\] is for task 'classification'"),
        ({"data": {"path": ""}}, "task 'steps' needs data.path"),
        ({"data": {"path": "no/such/dir"}}, "data.path = 'no/such/dir' is not a folder"),
        ({"task": "regression"}, r"task = 'regression' is not allowed; allowed: 'classification', 'steps'"),
    ],
)
def test_bad_config(tmp_path, raw, match):
    full = {"name": "s", "task": "steps", "data": {"path": str(tmp_path)}}
    for k, v in raw.items():
        full[k] = {**full[k], **v} if isinstance(v, dict) and k in full else v
    with pytest.raises(ConfigError, match=match):
        parse_config(full, base_dir=tmp_path)


def test_train_refuses_a_steps_config(tmp_path):
    from gaitml.pipeline import train_config

    cfg = parse_config({"name": "s", "task": "steps", "data": {"path": str(tmp_path)}})
    with pytest.raises(ConfigError, match="gaitml train needs a classification config"):
        train_config(cfg, out_dir=tmp_path / "m")


def test_run_writes_tables(ifsm_recs, tmp_path):
    out = tmp_path / "run"
    summary = run_steps_real(out, data_dir=tmp_path, detectors=["single-peak", "ifsm"], recordings=ifsm_recs)
    table = pd.read_csv(out / "per_recording.csv")
    assert len(table) == 4 and set(table["detector"]) == {"single-peak", "ifsm"}
    counts = {name: [len(get_detector(name).detect(r).steps_) for r in ifsm_recs] for name in ("single-peak", "ifsm")}
    assert summary["ifsm"]["single-peak"]["acceleration_flat_holding_1"]["n_detected"] == counts["single-peak"][0]
    assert summary["ifsm_first10_period_mad_s"] <= 0.03
    assert json.loads((out / "summary.json").read_text())["tolerance_s"] == 0.25
    # the report's row: the detector's counts of the two files, then the true counts (paper 000)
    assert f"| ifsm | {counts['ifsm'][0]} | {counts['ifsm'][1]} | 284 | 319 |" in (out / "report.md").read_text()


def test_gaitml_evaluate_runs_a_steps_config(tmp_path, capsys):
    """`gaitml evaluate` on a steps config: the IFSM set only, two detectors, their counts and the published truth."""
    data = shared()
    cfg_path = tmp_path / "steps-ifsm.toml"
    cfg_path.write_text(
        'name = "steps-ifsm"\ntask = "steps"\n[data]\npath = "nowhere"\nsets = ["ifsm-flat-phone"]\n[steps]\ndetectors = ["ifsm", "adfsm"]\n'
    )
    assert main(["evaluate", str(cfg_path), "--data", str(data), "--out", str(tmp_path / "run"), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["task"] == "steps" and result["run_dir"] == str(tmp_path / "run")
    ifsm_2 = read_recording(shared("ifsm-flat-phone", "acceleration_flat_holding_2.xlsx"))
    assert result["ifsm"]["ifsm"]["acceleration_flat_holding_2"]["n_detected"] == len(get_detector("ifsm").detect(ifsm_2).steps_)
    assert result["ifsm"]["adfsm"]["acceleration_flat_holding_1"]["n_true"] == 284
    cfg = load_config(cfg_path, check_paths=False).with_data_path(data)
    again = evaluate_steps_config(cfg, out_dir=tmp_path / "run2")
    assert again["ifsm"] == result["ifsm"]


def test_evaluate_data_option_errors(tmp_path, capsys):
    assert main(["evaluate", str(ROOT / "experiments" / "steps-real.toml"), "--data", str(tmp_path / "missing")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["evaluate", str(ROOT / "experiments" / "paper-svm.toml"), "--data", str(tmp_path)]) == 2
    assert "simulates its data" in capsys.readouterr().err
