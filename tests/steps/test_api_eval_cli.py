"""Registry and common API of every detector, step metrics, and the `gaitml steps` command."""

import io
import json
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import STEP_DETECTORS, main
from gaitml.errors import InputError
from gaitml.evaluation.steps import count_accuracy, evaluate_steps, match_steps
from gaitml.recording import Recording
from gaitml.steps import DETECTORS, detect_steps, detector_names, get_detector, make_step_table
from tests.steps.conftest import synthetic_walk

OWN = [n for n in detector_names() if n != "zupt-magnitude"]


def test_registry_matches_cli():
    assert set(detector_names()) == set(STEP_DETECTORS)
    assert set(OWN) <= set(DETECTORS)


def test_unknown_detector_lists_names():
    with pytest.raises(InputError, match="valid names: single-peak, ifsm"):
        get_detector("nope")
    with pytest.raises(InputError, match="bad parameters"):
        get_detector("single-peak", bogus=1)


def test_zupt_magnitude_lazy():
    try:
        cls = DETECTORS["zupt-magnitude"]
    except Exception as exc:  # the other helper's module may be missing: a clear error
        assert "not available" in str(exc)
    else:
        assert cls.__name__ == "ZuptMagnitudeStepDetector"


@pytest.mark.parametrize("name", OWN)
def test_detector_api(name):
    rec = synthetic_walk(n_steps=30, fs=50.0)
    det = get_detector(name)
    assert det.detect(rec) is det
    st = det.steps_
    for col in ("start", "peak", "end", "t_start_s", "t_peak_s", "t_end_s", "period_s"):
        assert col in st.columns
    assert st.attrs["event"] in st.columns
    assert (st["start"] <= st["end"]).all() and (st["end"] <= rec.n_samples).all()
    assert abs(len(st) - 30) <= 2, name
    pd.testing.assert_frame_equal(detect_steps(rec, name), st)


@pytest.mark.parametrize("name", OWN)
def test_phone_at_rest_has_no_steps(name):
    rng = np.random.default_rng(0)
    rec = Recording.from_arrays(np.tile([0.0, 0.0, 9.80665], (1500, 1)) + rng.normal(0, 0.02, (1500, 3)), 50.0)
    assert len(get_detector(name).detect(rec).steps_) == 0


@pytest.mark.parametrize("name", OWN)
def test_too_short_or_wrong_input(name):
    short = Recording.from_arrays(np.tile([0.0, 0.0, 9.81], (20, 1)), 50.0)
    with pytest.raises(InputError, match="too short"):
        get_detector(name).detect(short)
    with pytest.raises(InputError, match="Recording"):
        get_detector(name).detect(np.zeros((100, 3)))


def test_count_accuracy():
    assert count_accuracy(284, 284) == 1.0
    assert count_accuracy(279, 284) == pytest.approx(1 - 5 / 284)
    with pytest.raises(InputError):
        count_accuracy(3, 0)


def test_matching_is_optimal_not_greedy():
    # greedy-by-distance would pair 0.46 with 0.60 first and leave 0.75 unmatched
    pairs = match_steps([0.46, 0.75], [0.30, 0.60], tolerance_s=0.165)
    assert pairs.tolist() == [[0, 0], [1, 1]]


def test_matching_one_to_one_and_tolerance():
    pairs = match_steps([1.0, 1.01, 5.0], [1.0, 3.0], tolerance_s=0.25)
    assert pairs.tolist() == [[0, 0]]
    assert len(match_steps([], [1.0])) == 0


def test_evaluate_steps_values():
    true = np.arange(10) * 0.5 + 1.0
    det = np.delete(true, 3) + 0.02
    det = np.append(det, 20.0)  # one false positive
    table = make_step_table(np.zeros(10, int), np.rint(det * 100).astype(int), np.zeros(10, int), 100.0, event="t_peak_s")
    ev = evaluate_steps(table, true)
    assert ev["n_detected"] == 10 and ev["n_matched"] == 9
    assert ev["precision"] == pytest.approx(0.9) and ev["recall"] == pytest.approx(0.9)
    assert ev["timing_offset_s"] == pytest.approx(0.02)
    assert ev["period_error_s"] == pytest.approx(0.0, abs=1e-9)
    assert ev["count_accuracy"] == 1.0


def _cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def test_cli_json_contract(ifsm_recs, tmp_path):
    path = ifsm_recs[0].meta["source"]
    out_csv = tmp_path / "steps.csv"
    rc, out, err = _cli(["steps", path, "--detector", "single-peak", "--json", "--out", str(out_csv)])
    assert rc == 0 and out.count("\n") == 1
    obj = json.loads(out)
    assert {"detector", "sampling_rate_hz", "n_steps", "steps"} <= set(obj)
    n = len(get_detector("single-peak").detect(ifsm_recs[0]).steps_)
    assert obj["n_steps"] == n == len(obj["steps"]) and obj["sampling_rate_hz"] == 50.0
    assert set(obj["steps"][0]) == {"t_s", "period_s"}
    assert obj["evaluation"]["count_accuracy"] == pytest.approx(count_accuracy(n, 284)) and obj["evaluation"]["count_accuracy"] >= 0.98
    assert len(pd.read_csv(out_csv)) == n


def test_cli_text_and_errors(ifsm_recs, tmp_path):
    rc, out, _ = _cli(["steps", ifsm_recs[1].meta["source"], "--detector", "ifsm"])
    assert rc == 0 and "319 steps" in out and "count accuracy 100.00 %" in out
    rc, _, err = _cli(["steps", ifsm_recs[1].meta["source"], "--detector", "nope"])
    assert rc == 2 and "invalid choice" in err
    short = tmp_path / "short.csv"
    short.write_text("t,acc_x,acc_y,acc_z\n" + "".join(f"{i / 50},0,0,9.81\n" for i in range(10)))
    rc, out, err = _cli(["steps", str(short), "--json"])
    assert rc == 2 and out == "" and "too short" in err
