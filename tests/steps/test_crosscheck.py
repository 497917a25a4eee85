"""The single-peak count cross-check (gaitml.steps.crosscheck): under- and overcounts, library, CLI, chunked inputs."""

from __future__ import annotations

import dataclasses
import json

import pytest

from gaitml.cli import main
from gaitml.simulate import Subject, simulate_recording
from gaitml.steps import get_detector
from gaitml.steps._base import count_accuracy
from gaitml.steps.crosscheck import MIN_ADAPTIVE_STEPS, OVERCOUNT_RATIO, UNDERCOUNT_RATIO, compare_counts, count_warning
from tests.conftest import ROOT, shared

SAMPLE = ROOT / "data" / "samples" / "S02-mixed.csv"  # a calm walker (hand gain 0.30)
DARIO_FRONT_POCKET = ("oxford-step-counter", "optimisation", "data", "Samsung_Dario_Hard_FrontPocket_1")


def _walk(gain: float, duration_s: float = 40.0):
    return simulate_recording(dataclasses.replace(Subject(), hand_gain=gain), modes=("walk",), duration_s=duration_s, seed=5)


def test_a_calm_walker_is_warned_about_and_a_vigorous_one_is_not():
    calm, vigorous = _walk(0.3), _walk(1.0)
    n_calm = len(get_detector("single-peak").detect(calm).steps_)
    assert n_calm < 0.85 * calm.reference["n_steps_true"]
    msg = count_warning(calm, n_calm, "single-peak")
    assert msg is not None and "adaptive" in msg and "too calm" in msg and str(n_calm) in msg and "\n" not in msg
    n_vig = len(get_detector("single-peak").detect(vigorous).steps_)
    assert n_vig == vigorous.reference["n_steps_true"]
    assert count_warning(vigorous, n_vig, "single-peak") is None


def test_only_fixed_threshold_detectors_and_enough_steps_are_checked():
    calm = _walk(0.3)
    assert count_warning(calm, 0, "adaptive") is None
    assert count_warning(calm, 0, "ifsm") is None
    short = _walk(0.3, duration_s=4.0)  # fewer than 10 steps
    assert count_warning(short, 0, "single-peak") is None
    assert compare_counts(1000, MIN_ADAPTIVE_STEPS - 1, "single-peak") is None
    assert compare_counts(0, 1000, "adaptive") is None and compare_counts(5000, 1000, "fsm") is None


def test_compare_counts_warns_below_and_above_the_ratios():
    """The two ratios bound a band around adaptive's count; outside it one line says which way."""
    assert (UNDERCOUNT_RATIO, OVERCOUNT_RATIO) == (0.85, 1.11)
    assert compare_counts(85, 100, "single-peak") is None and compare_counts(111, 100, "single-peak") is None
    under, over = compare_counts(84, 100, "single-peak"), compare_counts(112, 100, "single-peak")
    assert "found 84 steps where the adaptive detector finds 100" in under and "too calm" in under
    assert "found 112 steps where the adaptive detector finds 100" in over and "more than once per step" in over
    assert "--detector adaptive" in under and "--detector adaptive" in over
    # the ratios are parameters (the report script scores other ones with the library's own decision)
    assert compare_counts(112, 100, "single-peak", overcount_ratio=1.2) is None
    assert compare_counts(88, 100, "single-peak", undercount_ratio=0.9) is not None


def test_steps_and_pdr_cli_print_one_warning_line_and_json_warnings(capsys):
    assert main(["steps", str(SAMPLE), "--detector", "single-peak", "--json"]) == 0
    out, err = capsys.readouterr()
    obj = json.loads(out)
    warn_lines = [line for line in err.splitlines() if line.startswith("gaitml: warning:")]
    assert len(warn_lines) == 1 and obj["warnings"] == [warn_lines[0].removeprefix("gaitml: warning: ")]
    assert main(["steps", str(SAMPLE), "--detector", "adaptive", "--json"]) == 0
    out, err = capsys.readouterr()
    assert "warnings" not in json.loads(out) and "gaitml: warning:" not in err
    assert main(["pdr", str(SAMPLE), "--detector", "single-peak", "--json"]) == 0  # paper 003's fixed-threshold detector
    out, err = capsys.readouterr()
    assert len(json.loads(out)["warnings"]) == 1 and err.count("gaitml: warning:") == 1
    assert main(["pdr", str(SAMPLE), "--detector", "adaptive", "--json"]) == 0
    out, err = capsys.readouterr()
    assert "warnings" not in json.loads(out)


# -- chunked (long) inputs: gaitml steps via gaitml.chunked_run ---------------------------------------------------------


@pytest.fixture(scope="module")
def calm_long_csv(tmp_path_factory):
    """A calm hand-held walker (hand gain 0.3), 150 s at 50 Hz: single-peak keeps about a quarter of the steps."""
    from gaitml.io import write_gaitml_csv

    p = tmp_path_factory.mktemp("calm") / "calm.csv"
    write_gaitml_csv(_walk(0.3, duration_s=150.0), p)
    return p


def test_long_steps_counts_the_crosscheck_detector_per_chunk_core(calm_long_csv):
    """count_also: adaptive's steps anchored in each chunk's core, summed, equal its whole-file count here."""
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording

    whole = len(get_detector("adaptive").detect(read_recording(calm_long_csv)).steps_)
    chunked = long_steps(calm_long_csv, "single-peak", chunk_s=30.0, margin_s=5.0, progress=False, count_also="adaptive")
    assert chunked.attrs["count_also"] == {"detector": "adaptive", "n_steps": whole}
    assert len(chunked) < UNDERCOUNT_RATIO * whole  # the undercount the warning is about
    assert "count_also" not in long_steps(calm_long_csv, "single-peak", chunk_s=30.0, margin_s=5.0, progress=False).attrs


def _large(monkeypatch):
    import gaitml.io.chunked as ch

    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)


def test_chunked_steps_cli_warns_once_on_a_calm_long_input(calm_long_csv, monkeypatch, capsys):
    _large(monkeypatch)
    assert main(["steps", str(calm_long_csv), "--detector", "single-peak", "--json"]) == 0
    out, err = capsys.readouterr()
    obj = json.loads(out)
    assert obj["chunked"]
    warn_lines = [line for line in err.splitlines() if line.startswith("gaitml: warning:")]
    assert len(warn_lines) == 1 and obj["warnings"] == [warn_lines[0].removeprefix("gaitml: warning: ")]
    assert f"found {obj['n_steps']} steps" in obj["warnings"][0] and "too calm" in obj["warnings"][0]
    assert main(["steps", str(calm_long_csv), "--detector", "single-peak"]) == 0  # the text output warns too
    assert capsys.readouterr().err.count("gaitml: warning:") == 1
    assert main(["steps", str(calm_long_csv), "--detector", "adaptive", "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["chunked"] and "warnings" not in json.loads(out) and "gaitml: warning:" not in err


# -- real walks ----------------------------------------------------------------------------------------------------


@pytest.mark.realdata
def test_real_walks_warned_only_where_single_peak_undercounts():
    """IFSM (single-peak exact) is not warned about; Jamie's calm Samsung walk (70 of 265) is."""
    from gaitml.io import read_recording

    for name in ("acceleration_flat_holding_1.xlsx", "acceleration_flat_holding_2.xlsx"):
        rec = read_recording(shared("ifsm-flat-phone", name))
        n = len(get_detector("single-peak").detect(rec).steps_)
        assert count_warning(rec, n, "single-peak") is None
    rec = read_recording(shared("oxford-step-counter", "optimisation", "data", "Samsung_Jamie_Hard_InHand_1"))
    n = len(get_detector("single-peak").detect(rec).steps_)
    assert n < 0.5 * len(rec.reference["steps_t_s"])
    assert "too calm" in count_warning(rec, n, "single-peak")


@pytest.mark.realdata
def test_steps_cli_warns_on_a_real_overcount_whole_and_chunked(monkeypatch, capsys, tmp_path):
    """Dario's front-pocket walk (306 true steps): single-peak counts far more, adaptive about right, and the steps command
    warns once with the two counts, on the file as a whole and in 60 s chunks (which count the same steps)."""
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording, write_gaitml_csv

    folder = shared(*DARIO_FRONT_POCKET)
    rec = read_recording(folder)
    n_adaptive = len(get_detector("adaptive").detect(rec).steps_)
    assert main(["steps", str(folder), "--detector", "single-peak", "--json"]) == 0
    out, err = capsys.readouterr()
    obj = json.loads(out)
    n_single = obj["n_steps"]
    assert obj["n_steps_true"] == 306 and n_single > 1.15 * 306 and count_accuracy(n_adaptive, 306) >= 0.95
    assert err.count("gaitml: warning:") == 1
    assert obj["warnings"] == [compare_counts(n_single, n_adaptive, "single-peak")] and "more than once per step" in obj["warnings"][0]
    csv = tmp_path / "dario.csv"
    write_gaitml_csv(rec, csv)
    st = long_steps(csv, "single-peak", chunk_s=60.0, margin_s=10.0, progress=False, count_also="adaptive")
    assert (len(st), st.attrs["count_also"]["n_steps"]) == (n_single, n_adaptive)
    _large(monkeypatch)
    assert main(["steps", str(csv), "--detector", "single-peak", "--json"]) == 0
    out, err = capsys.readouterr()
    obj = json.loads(out)
    assert (
        obj["chunked"] and obj["warnings"] == [compare_counts(n_single, n_adaptive, "single-peak")] and err.count("gaitml: warning:") == 1
    )
