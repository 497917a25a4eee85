"""The PDR pipeline and the `gaitml pdr` command on the synthetic walks of tests/pdr/synth.py."""

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.evaluation.trajectory import closure_error
from gaitml.io import write_gaitml_csv
from gaitml.pdr import run_pdr
from gaitml.pdr.pipeline import modes_from_labels, modes_from_windows
from tests.pdr.synth import synth_walk

# a square walked while turning only twice: forward, left side steps, backward, right side steps
LEGS = [("walk", 20, np.pi / 2), ("side_left", 14, np.pi / 2), ("backward", 20, np.pi / 2), ("side_right", 14, 0.0)]


@pytest.fixture(scope="module")
def rec():
    return synth_walk(LEGS, pitch_deg=20, noise=0.05)


@pytest.mark.parametrize("heading", ["gyro", "hde", "dwpca"])
def test_multi_state_pdr_follows_the_truth_and_forward_only_does_not(rec, heading):
    # the synthetic walk's 68 steps are paper 003 peaks; single-peak finds exactly them
    res = run_pdr(rec, heading=heading, modes="true", step_length="reference", detector="single-peak")
    assert res.n_steps == 68
    truth_end = rec.reference["trajectory"][["x_m", "y_m"]].to_numpy()[-1]
    err_multi = np.linalg.norm(np.array(res.end_xy_m) - truth_end)
    assert err_multi < 1.0, res.end_xy_m
    fwd = run_pdr(rec, heading="gyro", modes="forward", step_length="reference", detector="single-peak")
    assert np.linalg.norm(np.array(fwd.end_xy_m) - truth_end) > 10.0
    assert list(res.trajectory.columns) == ["t_s", "x_m", "y_m", "heading_rad", "mode", "step_length_m"]
    assert len(res.trajectory) == res.n_steps + 1 and res.trajectory["mode"].iloc[0] == "start"


def test_modes_from_labels_and_windows():
    labels = np.array(["walk"] * 10 + ["run"] * 10)
    assert modes_from_labels(labels, [0, 8, 12], [10, 15, 20]).tolist() == ["walk", "run", "run"]
    w = pd.DataFrame({"t_start_s": [0.0, 0.75, 1.5], "t_end_s": [1.5, 2.25, 3.0], "mode": ["walk", "side_left", "run"]})
    assert modes_from_windows(w, [0.1, 1.4, 2.2, 9.0]).tolist() == ["walk", "side_left", "run", "run"]


def test_closure_is_scale_free_through_the_pipeline(rec):
    from gaitml.pdr.step_length import StepLengthModel

    a = run_pdr(rec, heading="gyro", modes="true")
    big = StepLengthModel({m: (k, tuple(2.5 * p for p in params)) for m, (k, params) in StepLengthModel().coefficients_in_use().items()})
    b = run_pdr(rec, heading="gyro", modes="true", step_length=big)
    assert closure_error(b.trajectory[["x_m", "y_m"]].to_numpy())[1] == pytest.approx(
        closure_error(a.trajectory[["x_m", "y_m"]].to_numpy())[1]
    )


@pytest.mark.parametrize(
    ("kw", "match"),
    [({"heading": "compass"}, "heading source"), ({"modes": "guess"}, "mode source"), ({"modes": "model"}, "needs a model")],
)
def test_bad_arguments(rec, kw, match):
    with pytest.raises(InputError, match=match):
        run_pdr(rec, **kw)


def test_no_gyro_is_a_clear_error(rec):
    with pytest.raises(InputError, match="gyr"):
        run_pdr(rec.replace(gyr=None), modes="forward")


def test_cli_json_plot_and_out(rec, tmp_path, capsys):
    path = tmp_path / "walk.csv"
    write_gaitml_csv(rec, path)
    png, out = tmp_path / "t.png", tmp_path / "t.csv"
    argv = ["--detector", "single-peak"]  # the synthetic walk's 68 paper 003 peaks
    assert main(["pdr", str(path), "--json", "--plot", str(png), "--out", str(out), "--heading", "gyro", *argv]) == 0
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    assert set(obj) == {"n_steps", "distance_m", "end_xy_m", "trajectory", "gyro_bias", "rate_check"}
    # the step detector's rate check (gaitml.steps._rate): the synthetic walk's rate is not below single-peak's floor
    assert obj["rate_check"]["detector"] == "single-peak" and obj["rate_check"]["below"] is False
    assert obj["rate_check"]["n_steps_below"] == 0
    assert obj["n_steps"] == 68 and len(obj["trajectory"]) == 69
    assert set(obj["trajectory"][0]) == {"t_s", "x_m", "y_m", "heading_rad", "mode"}
    assert "labels" in cap.err  # it says where the modes came from
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(pd.read_csv(out)) == 69
    # without labels: forward-only, said on stderr
    write_gaitml_csv(rec.replace(labels=None), tmp_path / "nolab.csv")
    assert main(["pdr", str(tmp_path / "nolab.csv"), "--json", *argv]) == 0
    cap = capsys.readouterr()
    assert "forward" in cap.err and json.loads(cap.out)["n_steps"] == 68
    assert main(["pdr", str(path), "--modes", "model"]) == 2


def test_calibration_from_reference_steps_fits_lengths_and_polarity():
    from gaitml.pdr.calibrate import calibrate_from_reference, calibrate_walk_distance, match_reference_steps

    rec = synth_walk([("walk", 30, np.pi / 2), ("backward", 30, 0.0)], step_length_m=0.62)
    cal = calibrate_from_reference(rec, detector="single-peak")  # the detector the PDR below uses
    assert cal.n_matched == cal.n_detected == 60
    feats_modes = ["walk"] * 30 + ["backward"] * 30
    res = run_pdr(rec, modes="true", heading="gyro", step_length=cal.step_length, detector="single-peak")
    assert np.allclose(res.steps["step_length_m"], 0.62, atol=1e-6)
    assert cal.dwpca.polarity == {"backward": 1.0, "walk": 1.0}  # the learned polarity, as a parameter of the configured source
    assert res.steps["mode"].tolist() == feats_modes
    m = calibrate_walk_distance(synth_walk([("walk", 40, 0.0)]), 30.0, detector="single-peak")
    assert run_pdr(
        synth_walk([("walk", 40, 0.0)]), modes="true", heading="gyro", step_length=m, detector="single-peak"
    ).distance_m == pytest.approx(30.0)
    assert match_reference_steps([0.0, 1.0, 5.0], [0.05, 1.2]).tolist() == [0, -1, -1]
