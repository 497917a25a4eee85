"""Step-length calibration from a truth trajectory (paper 003 sec. 4.1, eqs. 12-13), several recordings per mode."""

from __future__ import annotations

import json
import os

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.pdr import run_pdr
from gaitml.pdr.calibrate import (
    MAX_TRUTH_GAP_S,
    calibrate_from_truth,
    fit_step_lengths,
    main,
    step_length_samples,
    true_step_lengths,
)
from gaitml.pdr.step_length import StepLengthModel
from gaitml.simulate import sample_subjects
from gaitml.simulate.dataset import simulate_recording, write_simulation
from tests.conftest import ROOT


@pytest.fixture(scope="module")
def subject():
    return sample_subjects(1, 5)[0]


def _sim(subject, mode: str, seed: int, duration_s: float = 60.0):
    return simulate_recording(subject, route="straight", duration_s=duration_s, modes=(mode,), seed=seed, meta={"id": f"{mode}{seed}"})


def _true_distance(rec) -> float:
    traj = rec.reference["trajectory"]
    return float(np.linalg.norm(np.diff(traj[["x_m", "y_m"]].to_numpy(float), axis=0), axis=1).sum())


def test_true_step_lengths_follow_the_walker_and_skip_pauses_and_gaps():
    t = np.arange(0, 20, 1 / 60)
    body = np.column_stack([t * 1.0, np.zeros_like(t)])  # 1 m/s east
    steps = np.array([1.0, 1.5, 2.0, 2.5, 5.0, 5.5, 25.0])
    out = true_step_lengths(steps, t, body)
    assert np.isnan(out[0]) and np.isnan(out[4]) and np.isnan(out[6])  # first, after a 2.5 s pause, outside the capture
    np.testing.assert_allclose(out[[1, 2, 3, 5]], 0.5, atol=1e-9)
    # the markers lost for longer than MAX_TRUTH_GAP_S between 1.6 and 2.4 s: the pairs spanning it get no length
    lost = (t > 1.6) & (t < 1.6 + MAX_TRUTH_GAP_S + 0.3)
    out = true_step_lengths(steps, t, body, lost=lost)
    assert np.isnan(out[2]) and np.isnan(out[3]) and out[1] == pytest.approx(0.5)
    # a short loss (a frame or two) is bridged
    out = true_step_lengths(steps, t, body, lost=(t > 1.7) & (t < 1.75))
    np.testing.assert_allclose(out[[1, 2, 3]], 0.5, atol=1e-9)


def test_calibration_recovers_the_walk_and_run_lengths_on_other_simulated_walks(subject):
    """Fitted on one walk and one run with their reference paths; scored on other seeds of the same walker."""
    model = calibrate_from_truth([_sim(subject, "walk", 1), _sim(subject, "run", 2)], ["walk", "run"])
    assert sorted(model.fitted_modes_) == ["run", "walk"]
    assert model.coefficients_["walk"][0] == "linear" and model.coefficients_["run"][0] == "weinberg"
    info = model.calibration_["modes"]
    assert info["walk"]["n_steps"] > 80 and info["run"]["n_steps"] > 120
    # the body track's mean step is the walker's true one (the simulator's reference steps)
    assert info["walk"]["mean_true_length_m"] == pytest.approx(subject.walk_step_length_m, rel=0.05)
    assert info["run"]["mean_true_length_m"] == pytest.approx(subject.run_step_length_m, rel=0.05)
    for mode, seed in (("walk", 3), ("run", 4)):
        rec = _sim(subject, mode, seed)
        ratio = run_pdr(rec, modes="true", step_length=model).distance_m / _true_distance(rec)
        uncal = run_pdr(rec, modes="true").distance_m / _true_distance(rec)
        assert 0.92 <= ratio <= 1.08, (mode, ratio)
        assert abs(ratio - 1) <= abs(uncal - 1) + 0.01  # no worse than the stated defaults


def test_labels_give_the_modes_of_a_mixed_recording(subject):
    rec = simulate_recording(subject, route="straight", duration_s=120.0, modes=("walk", "run"), seed=7)
    samples = step_length_samples(rec, "labels")
    assert set(samples["mode"]) == {"walk", "run"}
    assert np.isfinite(samples["true_length_m"]).mean() > 0.8
    run_mean = samples.loc[samples["mode"] == "run", "true_length_m"].mean()
    walk_mean = samples.loc[samples["mode"] == "walk", "true_length_m"].mean()
    assert run_mean > walk_mean * 1.2  # the simulated runner strides longer than he walks
    # fitted from the labels: every motion mode with enough steps; a paused walk's standing steps are left out
    paused = simulate_recording(subject, route="straight", duration_s=120.0, modes=("walk", "run"), seed=7, pauses=True)
    model = calibrate_from_truth([paused], "labels", min_steps=10)
    assert {"walk", "run"} <= set(model.fitted_modes_)
    assert set(model.calibration_.get("labels_left_out", {})) <= set(np.unique(paused.labels)) - {"walk", "run"}
    with pytest.raises(InputError, match="no labelled mode has"):
        calibrate_from_truth([paused], "labels", min_steps=10_000)


def test_cli_fits_several_inputs_per_mode_and_gaitml_pdr_reads_the_json(subject, tmp_path, capsys):
    from gaitml.cli import main as gaitml_main

    walk, run = write_simulation([_sim(subject, "walk", 1), _sim(subject, "run", 2)], tmp_path / "cal")
    out = tmp_path / "sl.json"
    rc = main([str(walk), str(run), "--truth", "self", "--mode", "walk", "--mode", "run", "--out", str(out)])
    assert rc == 0, capsys.readouterr().err
    err = capsys.readouterr().err
    assert "walk: linear" in err and "run: weinberg" in err
    d = json.loads(out.read_text())
    assert d["format"] == "gaitml-step-length-v1" and sorted(d["fitted_modes"]) == ["run", "walk"]
    assert d["calibration"]["inputs"][1]["mode"] == "run"
    assert StepLengthModel.load(out).coefficients_in_use()["run"][0] == "weinberg"
    # gaitml pdr --step-length reads it
    (rec_file,) = write_simulation([_sim(subject, "walk", 3)], tmp_path / "test")
    assert gaitml_main(["pdr", str(rec_file), "--modes", "true", "--step-length", str(out), "--json"]) == 0
    obj = json.loads(capsys.readouterr().out)
    traj = pd.read_csv(rec_file.with_suffix(".trajectory.csv"))
    true_m = float(np.linalg.norm(np.diff(traj[["x_m", "y_m"]].to_numpy(float), axis=0), axis=1).sum())
    assert 0.92 <= obj["distance_m"] / true_m <= 1.08


def _write_one(subject, tmp_path, *, trajectory: bool = True, mode="walk", seed=1, duration_s=60.0):
    rec = _sim(subject, mode, seed, duration_s)
    if not trajectory:
        rec = rec.replace(reference={k: v for k, v in rec.reference.items() if k != "trajectory"})
    (f,) = write_simulation([rec], tmp_path)
    return f


@pytest.mark.parametrize(
    "case, expect",
    [
        ("no-truth", "carries no truth trajectory"),
        ("landmarks", "sparse landmarks"),
        ("few-steps", "have a true length"),
        ("mode-count", "--mode is given 3 times for 2 inputs"),
        ("several-no-truth", "pass --truth self"),
        ("distance-and-truth", "give one of them"),
        ("bad-mode-labels", "labels needs per-sample labels"),
        ("uneven-truth", "uneven.csv"),  # which input's truth cannot be used, with the reason
    ],
)
def test_cli_errors_are_one_line_and_leave_nothing(subject, tmp_path, capsys, case, expect):
    out = tmp_path / "sl.json"
    f = _write_one(subject, tmp_path / "rec", trajectory=case != "no-truth")
    args = [str(f), "--truth", "self", "--out", str(out)]
    if case == "landmarks":
        lm = tmp_path / "lm.csv"
        pd.DataFrame({"t": [0.0, 20.0, 40.0], "x_m": [0.0, 20.0, 40.0], "y_m": [0.0, 0.0, 0.0]}).to_csv(lm, index=False)
        args = [str(f), "--truth", str(lm), "--out", str(out)]
    elif case == "few-steps":  # a truth that only covers the first 4 s: a handful of steps
        tr = pd.read_csv(f.with_suffix(".trajectory.csv"))
        short = tmp_path / "short.csv"
        tr[tr["t"] < 4.0].rename(columns={"t": "t_s"}).to_csv(short, index=False)
        args = [str(f), "--truth", str(short), "--out", str(out)]
    elif case == "uneven-truth":  # a dense truth whose times are not on a uniform grid (every other point dropped at first)
        tr = pd.read_csv(f.with_suffix(".trajectory.csv")).rename(columns={"t": "t_s"})
        keep = np.r_[np.arange(0, 200, 2), np.arange(200, len(tr))]
        uneven = tmp_path / "uneven.csv"
        tr.iloc[keep].to_csv(uneven, index=False)
        args = [str(f), "--truth", str(uneven), "--out", str(out)]
    elif case == "mode-count":
        args = [str(f), str(f), "--truth", "self", "--mode", "walk", "--mode", "run", "--mode", "walk", "--out", str(out)]
    elif case == "several-no-truth":
        args = [str(f), str(f), "--out", str(out)]
    elif case == "distance-and-truth":
        args += ["--distance-m", "50"]
    elif case == "bad-mode-labels":
        from gaitml.io import read_recording, write_gaitml_csv

        rec = read_recording(f)
        nolab = tmp_path / "nolab" / "x.csv"
        nolab.parent.mkdir()
        write_gaitml_csv(rec.replace(labels=None), nolab)
        (tmp_path / "nolab" / "x.trajectory.csv").write_text(f.with_suffix(".trajectory.csv").read_text())
        args = [str(nolab), "--truth", "self", "--mode", "labels", "--out", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert expect in err and len(err.splitlines()) == 1 and err.startswith("error: ")
    if case == "uneven-truth":
        assert f.stem in err and "uniform rate" in err
    assert not out.exists()


def test_a_mode_with_no_steps_is_refused():
    samples = pd.DataFrame(
        {
            "mode": ["walk"] * 30,
            "true_length_m": np.full(30, 0.6),
            "freq_hz": np.linspace(1.6, 2.0, 30),
            "var_ms2sq": np.linspace(2, 4, 30),
            "a_max_ms2": np.full(30, 5.0),
            "a_min_ms2": np.full(30, -3.0),
        }
    )
    with pytest.raises(InputError, match="no steps of mode 'run'"):
        fit_step_lengths(samples, modes=["walk", "run"])
    model = fit_step_lengths(samples)
    assert model.predict(samples, samples["mode"]) == pytest.approx(np.full(30, 0.6), abs=1e-6)
    with pytest.raises(InputError, match="no steps were detected"):
        fit_step_lengths(samples.iloc[:0])


def test_tyrex_lengths_fitted_on_two_people_carry_to_the_third(shared_data):
    """Fitted on Jakob's and Thibaud's NoDist walks and runs against the motion capture; Guillaume's steps
    come out within 25 % of his true walked distance (walk and run apart; the uncalibrated lengths are
    1.3-1.9 x): the distance ratio of the step-length stage held out, without the heading. The margin is
    the spread from one left-out person to the next (experiments/reports/tyrex-pdr.md: per person 0.77-1.13
    walking, 0.80-1.07 running); Guillaume runs with longer steps than the other two (0.72 vs ~0.62 m)."""
    from gaitml.io import read_segments

    root = shared_data / "tyrex-attitude" / "android"
    if not root.is_dir():
        pytest.skip("tyrex-attitude not in the shared data")
    motions = {"Texting": "walk", "FrontPocket": "walk", "Swinging": "walk", "RunningHand": "run", "RunningPocket": "run"}

    def samples_of(person):
        parts = []
        for motion, mode in motions.items():
            for folder in sorted(root.parent.glob(f"*/{person}_*_NoDist_{motion}")):  # the three phones
                for seg in read_segments(folder):
                    parts.append(step_length_samples(seg, mode))
        return pd.concat(parts, ignore_index=True)

    train = pd.concat([samples_of("Jakob"), samples_of("Thibaud")], ignore_index=True)
    model = fit_step_lengths(train, modes=["walk", "run"])
    test = samples_of("Guillaume")
    ok = np.isfinite(test["true_length_m"].to_numpy(float))
    pred = model.predict(test[ok], test.loc[ok, "mode"])
    uncal = StepLengthModel().predict(test[ok], test.loc[ok, "mode"])
    for mode in ("walk", "run"):
        sel = (test.loc[ok, "mode"] == mode).to_numpy()
        true_m = test.loc[ok, "true_length_m"].to_numpy(float)[sel].sum()
        ratio = pred[sel].sum() / true_m
        assert 0.75 <= ratio <= 1.25, (mode, ratio)
        assert abs(ratio - 1) < abs(uncal[sel].sum() / true_m - 1)  # better than the uncalibrated lengths (1.3-1.9 x)


def test_cli_on_a_tyrex_recording_with_a_sensor_gap_uses_its_stretches(shared_data, tmp_path, capsys):
    """Thibaud_Nexus5_Dist_FrontPocket has a sensor gap: read in stretches, the 0.1 s one left out and said so."""
    folder = shared_data / "tyrex-attitude" / "android" / "Thibaud_Nexus5_Dist_FrontPocket"
    if not folder.is_dir():
        pytest.skip("tyrex-attitude not in the shared data")
    out = tmp_path / "sl.json"
    assert main([str(folder), "--truth", "self", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "shorter than 5 s left out" in err and "walk: linear" in err
    info = json.loads(out.read_text())["calibration"]["modes"]["walk"]
    assert info["n_recordings"] == 1 and info["n_steps"] > 50
    assert 0.3 < info["mean_true_length_m"] < 0.7  # a walker's step in a 5 m room (0.39-0.54 m)


def test_steps_outside_the_calibration_are_said(subject, tmp_path, capsys):
    """A walk-only calibration given running steps (forward-only) extrapolates: the steps are flagged, in the
    step table, the JSON and one warning line; another walk of the same walker is (nearly) not flagged."""
    from gaitml.cli import main as gaitml_main

    model = calibrate_from_truth([_sim(subject, "walk", 1)], "walk")
    band = model.calibration_["modes"]["walk"]["fitted_range"]
    assert set(band) == {"freq_hz", "var_ms2sq"} and band["freq_hz"][0] < subject.walk_cadence_hz < band["freq_hz"][1]
    walk, run = _sim(subject, "walk", 3), _sim(subject, "run", 4)
    res_walk = run_pdr(walk, modes="forward", step_length=model)
    res_run = run_pdr(run, modes="forward", step_length=model)
    assert res_walk.steps["step_length_outside_fit"].mean() < 0.1
    assert res_run.steps["step_length_outside_fit"].mean() > 0.9
    assert res_run.info["step_length_outside_fit"] == int(res_run.steps["step_length_outside_fit"].sum())
    assert "step_length_outside_fit" not in run_pdr(run, modes="forward").steps  # no calibration record: no flags
    # through the command line: JSON count and one warning line
    out = tmp_path / "walk-only.json"
    model.save(out)
    assert StepLengthModel.load(out).outside_fit(res_run.steps, res_run.steps["mode"]).mean() > 0.9  # the record is saved
    (rec_file,) = write_simulation([run], tmp_path / "run")
    traj_csv = tmp_path / "traj.csv"
    argv = ["pdr", str(rec_file), "--modes", "forward", "--step-length", str(out), "--json", "--out", str(traj_csv)]
    assert gaitml_main(argv) == 0
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    assert obj["step_length_outside_fit"] > 0.9 * obj["n_steps"]
    lines = [ln for ln in cap.err.splitlines() if "outside the cadence / acceleration" in ln]
    assert len(lines) == 1 and "extrapolated" in lines[0]
    # which steps: per row of the JSON trajectory and a column of the written trajectory (the start row has none)
    rows = obj["trajectory"]
    assert rows[0]["step_length_outside_fit"] is None
    assert sum(bool(r["step_length_outside_fit"]) for r in rows[1:]) == obj["step_length_outside_fit"]
    table = pd.read_csv(traj_csv)
    assert len(table) == obj["n_steps"] + 1 and pd.isna(table["step_length_outside_fit"].iloc[0])
    assert int(table["step_length_outside_fit"].iloc[1:].astype(bool).sum()) == obj["step_length_outside_fit"]


def test_steps_of_a_mode_the_calibration_did_not_fit_are_said(subject):
    """A walk-only calibration with the modes given (as --model gives them): the run steps take the stated
    default K (uncalibrated, 1.5 x the distance on tyrex) and used to go unflagged because run had no band;
    with run calibrated too they are (nearly) not flagged. A step of a mode without coefficients takes the
    walk line and is checked against the walk band."""
    walk_only = calibrate_from_truth([_sim(subject, "walk", 1)], "walk")
    both = calibrate_from_truth([_sim(subject, "walk", 1), _sim(subject, "run", 2)], ["walk", "run"])
    run = _sim(subject, "run", 4)
    res = run_pdr(run, modes="true", step_length=walk_only)
    is_run = (res.steps["mode"] == "run").to_numpy()
    assert is_run.mean() > 0.8
    assert res.steps["step_length_outside_fit"].to_numpy()[is_run].all()
    assert run_pdr(run, modes="true", step_length=both).steps["step_length_outside_fit"].mean() < 0.1
    walk = run_pdr(_sim(subject, "walk", 3), modes="forward", step_length=walk_only)
    feats = walk.steps[["freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2"]]
    as_walk = walk_only.outside_fit(feats, np.full(len(feats), "walk"))
    np.testing.assert_array_equal(walk_only.outside_fit(feats, np.full(len(feats), "shuffle")), as_walk)


def test_a_calibration_used_with_another_step_detector_is_said(subject, tmp_path, capsys):
    """The true length of a step is the body's path since the detected step before, so a calibration holds for
    the detector it was fitted with (on tyrex, fitted with adaptive and run with autocorr a front-pocket walk came
    out 0.83 x, silently). gaitml pdr says so: the JSON, one warning line, the summary; not with the same one."""
    from gaitml.cli import main as gaitml_main

    model = calibrate_from_truth([_sim(subject, "walk", 1)], "walk")
    assert model.calibration_["detector"] == "adaptive"
    out = tmp_path / "walk.json"
    model.save(out)
    (rec_file,) = write_simulation([_sim(subject, "walk", 3)], tmp_path / "walk")
    for det, said in (("single-peak", True), ("adaptive", False)):
        assert gaitml_main(["pdr", str(rec_file), "--modes", "forward", "--step-length", str(out), "--detector", det, "--json"]) == 0
        cap = capsys.readouterr()
        obj = json.loads(cap.out)
        lines = [ln for ln in cap.err.splitlines() if "calibrated with" in ln]
        if said:
            assert obj["step_length_detector"] == {"calibrated_with": "adaptive", "detector": det}
            assert len(lines) == 1 and lines[0].startswith("gaitml: warning:") and "--detector adaptive" in lines[0]
        else:
            assert "step_length_detector" not in obj and not lines
    assert gaitml_main(["pdr", str(rec_file), "--modes", "forward", "--step-length", str(out), "--detector", "single-peak"]) == 0
    assert "calibrated with adaptive" in capsys.readouterr().out
    res = run_pdr(_sim(subject, "walk", 3), modes="forward", step_length=model, detector="single-peak")
    assert res.info["step_length_detector"] == {"calibrated_with": "adaptive", "detector": "single-peak"}


def test_the_calibration_module_runs_as_a_script_without_a_double_import_warning():
    """``python -m gaitml.pdr.calibrate`` must not find the module imported already by its package (runpy warns so);
    the package still serves its names."""
    import subprocess
    import sys

    import gaitml.pdr as pdr

    assert pdr.calibrate_from_truth is not None and "calibrate_from_truth" in pdr.__all__
    out = subprocess.run(
        [sys.executable, "-W", "error::RuntimeWarning", "-m", "gaitml.pdr.calibrate", "--help"],
        capture_output=True,
        text=True,
        cwd=str(ROOT),
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    assert out.returncode == 0 and "RuntimeWarning" not in out.stderr and "--truth" in out.stdout
