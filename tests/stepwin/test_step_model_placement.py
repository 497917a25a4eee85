"""``gaitml pdr --model`` with a step-window model gives every step its ``out_of_domain_reason``, as ``gaitml predict`` does.

A small step-window model is trained on simulated hand-held phones (no foot position, so the
foot-placement rule applies); a simulated foot-mounted sensor walks. ``gaitml predict`` reports
each step's reason; ``gaitml pdr --model`` classifies the same steps (the model's own detector) and
must report the same reasons: the same count of foot-mounted steps in the JSON and the warning line,
and the reason of each step in the result's step table.
"""

from __future__ import annotations

import json

import pytest

from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from gaitml.models._placement import FOOT_REASON
from gaitml.simulate.foot import simulate_foot


@pytest.fixture(scope="module")
def foot_and_model(step_model_dir):
    d = step_model_dir
    write_gaitml_csv(simulate_foot(modes=("walk",), duration_s=40.0, sampling_rate_hz=50.0, seed=613), d / "foot.csv")
    return d


def test_pdr_with_a_step_model_gives_each_step_its_reason(foot_and_model, capsys):
    d = foot_and_model
    assert main(["predict", str(d / "model"), str(d / "foot.csv"), "--json"]) == 0
    pred = json.loads(capsys.readouterr().out)
    n_foot = pred["out_of_domain_reasons"].get(FOOT_REASON, 0)
    assert n_foot >= 0.5 * len(pred["windows"])  # the foot walks all along
    assert main(["pdr", str(d / "foot.csv"), "--model", str(d / "model"), "--json"]) == 0
    res = capsys.readouterr()
    summary = json.loads(res.out)
    assert summary["n_steps"] == len(pred["windows"])  # the model's own detector: the same steps
    assert summary["foot_mounted_steps"] == n_foot
    assert f"{n_foot} of them because they rest between fast swings" in res.err


def test_run_pdr_step_table_carries_the_reasons(foot_and_model):
    from gaitml.io import read_recording
    from gaitml.models import load_model, predict_step_windows
    from gaitml.pdr import run_pdr

    d = foot_and_model
    model = load_model(d / "model")
    rec = read_recording(d / "foot.csv")
    res = run_pdr(rec, model=model, detector=model.window_detector)  # the steps the model's own detector finds
    table = predict_step_windows(model, rec)
    reasons = res.steps["out_of_domain_reason"].to_numpy(dtype=object)
    assert len(reasons) == len(table)
    assert list(reasons) == [str(r or "") for r in table["out_of_domain_reason"]]
    # every step flagged out of domain has its reason, and only those
    flagged = [v is False for v in res.steps["in_domain"]]
    assert [bool(r) for r in reasons] == flagged
    assert res.info["foot_mounted_steps"] == sum(r == FOOT_REASON for r in reasons) >= 0.5 * len(reasons)
