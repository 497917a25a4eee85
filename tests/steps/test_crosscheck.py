"""The single-peak undercount warning (gaitml.steps.crosscheck) in the library and the CLI."""

from __future__ import annotations

import dataclasses
import json

import pytest

from gaitml.cli import main
from gaitml.simulate import Subject, simulate_recording
from gaitml.steps import get_detector
from gaitml.steps.crosscheck import undercount_warning
from tests.conftest import ROOT, shared

SAMPLE = ROOT / "data" / "samples" / "S02-mixed.csv"  # a calm walker (hand gain 0.30)


def _walk(gain: float, duration_s: float = 40.0):
    return simulate_recording(dataclasses.replace(Subject(), hand_gain=gain), modes=("walk",), duration_s=duration_s, seed=5)


def test_a_calm_walker_is_warned_about_and_a_vigorous_one_is_not():
    calm, vigorous = _walk(0.3), _walk(1.0)
    n_calm = len(get_detector("single-peak").detect(calm).steps_)
    assert n_calm < 0.85 * calm.reference["n_steps_true"]
    msg = undercount_warning(calm, n_calm, "single-peak")
    assert msg is not None and "adaptive" in msg and str(n_calm) in msg and "\n" not in msg
    n_vig = len(get_detector("single-peak").detect(vigorous).steps_)
    assert n_vig == vigorous.reference["n_steps_true"]
    assert undercount_warning(vigorous, n_vig, "single-peak") is None


def test_only_fixed_threshold_detectors_and_enough_steps_are_checked():
    calm = _walk(0.3)
    assert undercount_warning(calm, 0, "adaptive") is None
    assert undercount_warning(calm, 0, "ifsm") is None
    short = _walk(0.3, duration_s=4.0)  # fewer than 10 steps
    assert undercount_warning(short, 0, "single-peak") is None


def test_steps_and_pdr_cli_print_one_warning_line_and_json_warnings(capsys):
    assert main(["steps", str(SAMPLE), "--detector", "single-peak", "--json"]) == 0
    out, err = capsys.readouterr()
    obj = json.loads(out)
    warn_lines = [line for line in err.splitlines() if line.startswith("gaitml: warning:")]
    assert len(warn_lines) == 1 and obj["warnings"] == [warn_lines[0].removeprefix("gaitml: warning: ")]
    assert main(["steps", str(SAMPLE), "--detector", "adaptive", "--json"]) == 0
    out, err = capsys.readouterr()
    assert "warnings" not in json.loads(out) and "gaitml: warning:" not in err
    assert main(["pdr", str(SAMPLE), "--json"]) == 0  # default single-peak
    out, err = capsys.readouterr()
    assert len(json.loads(out)["warnings"]) == 1 and err.count("gaitml: warning:") == 1
    assert main(["pdr", str(SAMPLE), "--detector", "adaptive", "--json"]) == 0
    out, err = capsys.readouterr()
    assert "warnings" not in json.loads(out)


@pytest.mark.realdata
def test_real_walks_warned_only_where_single_peak_undercounts():
    """IFSM (single-peak exact) is not warned about; Jamie's calm Samsung walk (70 of 265) is."""
    from gaitml.io import read_recording

    for name in ("acceleration_flat_holding_1.xlsx", "acceleration_flat_holding_2.xlsx"):
        rec = read_recording(shared("ifsm-flat-phone", name))
        n = len(get_detector("single-peak").detect(rec).steps_)
        assert undercount_warning(rec, n, "single-peak") is None
    rec = read_recording(shared("oxford-step-counter", "optimisation", "data", "Samsung_Jamie_Hard_InHand_1"))
    n = len(get_detector("single-peak").detect(rec).steps_)
    assert n < 0.5 * len(rec.reference["steps_t_s"])
    assert undercount_warning(rec, n, "single-peak") is not None
