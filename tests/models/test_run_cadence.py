"""The run-cadence rule (gaitml.models._predict.run_cadence_rule) and its place in every predict path.

People run above the walk-to-run transition cadence (140 steps/min) and walk below it; a window a
model reads ``run`` at a walking step cadence takes the model's best other mode, ``mode_raw`` keeps
``run`` and ``run_at_walking_cadence`` says the rule moved it. The rule's mechanics are checked on
hand-made tables and signals, then through the shipped model on a simulated run slowed to a walking
cadence (the same signal shapes at 1/1.4 of their rate: the model still reads run, the steps come at
a walking cadence), whole, in chunks, through ``gaitml predict`` and ``gaitml pdr``.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.models import _predict as P
from gaitml.models import load_model, predict_recording
from gaitml.models._predict import (
    RUN_CADENCE_DEFAULT_HZ,
    RUN_MIN_CADENCE_HZ,
    RUN_STRIDE_CADENCE_HZ,
    best_other_modes,
    model_inputs,
    run_cadence_rule,
    run_cadence_threshold,
    window_step_cadence,
)
from gaitml.recording import Recording
from gaitml.simulate import simulate_dataset
from tests.conftest import ROOT

FS = 50.0
DEMO = ROOT / "models" / "demo"
SLOWER = 1.4  # the simulated runs (2.4-3.2 steps/s) at 1/1.4 of their rate: 1.7-2.3 steps/s, a walking cadence


def _bounce(step_hz: float, seconds: float, fs: float = FS, amp: float = 3.0) -> Recording:
    """A phone lying flat on a walker bouncing at ``step_hz`` (|acc| oscillates once per step), no gyroscope."""
    t = np.arange(int(seconds * fs)) / fs
    rng = np.random.default_rng(3)
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), GRAVITY_MS2 + amp * np.sin(2 * np.pi * step_hz * t)])
    return Recording(acc=acc + 0.05 * rng.standard_normal(acc.shape), sampling_rate_hz=fs)


def _windows(n: int, length: int = 75, hop: int = 38) -> pd.DataFrame:
    s = np.arange(n, dtype=np.int64) * hop
    return pd.DataFrame({"start": s, "end": s + length})


@pytest.fixture(scope="module")
def slowed_run() -> Recording:
    """A simulated hand-held run and walk (seed 7) played 1.4 times slower: the demo model reads run at a walking cadence."""
    (rec,) = simulate_dataset(n_subjects=1, duration_s=40.0, modes=("run", "walk"), sampling_rate_hz=FS, seed=7, positions=("hand-flat",))
    return rec.replace(sampling_rate_hz=FS / SLOWER, check_units=False)


@pytest.fixture(scope="module")
def demo():
    return load_model(DEMO)


# ------------------------------------------------------------------ the rule on its own
def test_the_threshold_is_the_walk_to_run_transition_and_the_floor_half_the_fastest_step():
    from gaitml.steps.adaptive import MAX_STEP_HZ

    assert RUN_MIN_CADENCE_HZ * 60 == pytest.approx(140.0)
    assert RUN_STRIDE_CADENCE_HZ == pytest.approx(MAX_STEP_HZ / 2)
    assert run_cadence_threshold(None) == RUN_CADENCE_DEFAULT_HZ
    assert run_cadence_threshold(0) is None and run_cadence_threshold(2.5) == 2.5
    for bad in (-1.0, float("nan"), "fast"):
        with pytest.raises(InputError, match="0 turns the rule off"):
            run_cadence_threshold(bad)
    # steps/min given for steps/s (140), or a value under the floor that could move nothing (1.5): refused, not obeyed
    for bad in (140, 1.5, RUN_STRIDE_CADENCE_HZ, MAX_STEP_HZ + 0.1):
        with pytest.raises(InputError, match="steps/min"):
            run_cadence_threshold(bad)
    assert run_cadence_threshold(MAX_STEP_HZ) == MAX_STEP_HZ


def test_a_run_at_walking_cadence_is_moved_and_nothing_else_is():
    modes = ["run", "run", "run", "run", "walk", "run", "run"]
    raw = ["run", "run", "run", "walk", "walk", "run", "run"]
    cad = [1.9, 2.8, np.nan, 2.0, 1.9, 1.3, RUN_MIN_CADENCE_HZ]
    other = ["side_left", "walk", "walk", "backward", "walk", "walk", "walk"]
    out, moved = run_cadence_rule(modes, raw, cad, other)
    # 0: walking cadence -> the best other mode; 1: running cadence stays; 2: no step near it stays;
    # 3: the correction made it run -> its own raw answer; 4: not run; 5: under the floor (a run's stride?) stays;
    # 6: at the threshold is a run
    assert out.tolist() == ["side_left", "run", "run", "walk", "walk", "run", "run"]
    assert moved.tolist() == [True, False, False, True, False, False, False]
    for off in (None, 0):
        out, moved = run_cadence_rule(modes, raw, cad, other, min_cadence_hz=off)
        assert out.tolist() == modes and not moved.any()


def test_the_window_cadence_is_the_steps_cadence_and_nan_without_steps():
    for hz in (1.9, 2.8):
        c = window_step_cadence(_bounce(hz, 30.0), _windows(30))
        inner = c[3:-3]  # away from the recording's edges
        assert np.isfinite(inner).all() and np.allclose(inner, hz, rtol=0.05), (hz, inner)
    still = Recording(acc=np.tile([0.0, 0.0, GRAVITY_MS2], (1500, 1)), sampling_rate_hz=FS)
    assert np.isnan(window_step_cadence(still, _windows(30))).all()
    assert np.isnan(window_step_cadence(_bounce(1.9, 1.5), _windows(1))).all()  # too short for the detector


def test_the_best_other_mode_is_the_models_highest_score_without_run(demo, slowed_run):
    rec = P.model_view(demo, slowed_run.replace(sampling_rate_hz=FS, check_units=False))[0]
    w = P._windows_for(rec, demo.length_s, demo.overlap)
    X = model_inputs(demo, rec, w)
    pred = demo.estimator.predict(X).astype(str)
    other = best_other_modes(demo, X)
    assert "run" not in set(other) and (pred == "run").any()
    assert (other[pred != "run"] == pred[pred != "run"]).all()  # a window not read run keeps its answer
    scores = demo.estimator.decision_function(X)
    classes = demo.estimator.classes_.astype(str)
    best = scores[np.arange(len(X)), np.searchsorted(classes, other)]
    assert (scores[:, classes != "run"] <= best[:, None]).all()


# ------------------------------------------------------------------ through predict
def test_predict_moves_a_run_read_at_walking_cadence_and_keeps_the_models_answer(demo, slowed_run):
    on = predict_recording(demo, slowed_run, run_min_cadence_hz=RUN_MIN_CADENCE_HZ)
    off = predict_recording(demo, slowed_run, run_min_cadence_hz=0)
    moved = on["run_at_walking_cadence"].to_numpy(bool)
    assert moved.sum() >= 10  # 41 of 72 windows on this seed
    assert (on["mode_raw"] == off["mode_raw"]).all()
    assert (off["mode"][moved] == "run").all() and not (on["mode"][moved].isin(["run", "still"])).any()
    cad = on["step_cadence_hz"].to_numpy()[moved]
    assert ((cad >= RUN_STRIDE_CADENCE_HZ) & (cad < RUN_MIN_CADENCE_HZ)).all()
    assert (on["mode"][~moved] == off["mode"][~moved]).all()  # nothing else changes
    assert not off["run_at_walking_cadence"].any() and off["step_cadence_hz"].isna().all()
    assert on.attrs["run_cadence"] == {"min_cadence_hz": RUN_MIN_CADENCE_HZ}
    assert off.attrs["run_cadence"] == {"min_cadence_hz": None}


def test_a_run_at_running_cadence_is_left_alone(demo, slowed_run):
    run = slowed_run.replace(sampling_rate_hz=FS, check_units=False)  # the simulated run as it was: 2.4-3.2 steps/s
    t = predict_recording(demo, run, run_min_cadence_hz=RUN_MIN_CADENCE_HZ)
    fast = (t["mode_raw"] == "run").to_numpy() & (t["step_cadence_hz"].to_numpy() >= RUN_MIN_CADENCE_HZ)
    assert fast.sum() >= 10
    assert (t["mode"][fast] == "run").all() and not t["run_at_walking_cadence"][fast].any()


def test_the_default_follows_the_named_default(demo, slowed_run, monkeypatch):
    default = predict_recording(demo, slowed_run)
    assert default.attrs["run_cadence"] == {"min_cadence_hz": RUN_CADENCE_DEFAULT_HZ}
    assert default["run_at_walking_cadence"].sum() >= 10  # on by default
    monkeypatch.setattr(P, "RUN_CADENCE_DEFAULT_HZ", None)  # one constant turns it off in every path
    off = predict_recording(demo, slowed_run)
    assert off.attrs["run_cadence"] == {"min_cadence_hz": None} and not off["run_at_walking_cadence"].any()


def test_chunked_predict_moves_the_same_windows(demo, slowed_run, tmp_path):
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    path = tmp_path / "slowed.csv"
    write_gaitml_csv(slowed_run, path)
    whole = predict_recording(demo, read_recording(path), run_min_cadence_hz=RUN_MIN_CADENCE_HZ)
    chunked = long_predict(demo, path, chunk_s=20.0, progress=False, run_min_cadence_hz=RUN_MIN_CADENCE_HZ)
    assert len(whole) == len(chunked) and whole["run_at_walking_cadence"].sum() >= 10
    # the chunks find their own steps: a window near a chunk's edge may read another cadence
    assert (whole["run_at_walking_cadence"].to_numpy() == chunked["run_at_walking_cadence"].to_numpy()).mean() >= 0.9
    assert (whole["mode"].to_numpy() == chunked["mode"].to_numpy()).mean() >= 0.9
    off = long_predict(demo, path, chunk_s=20.0, progress=False, run_min_cadence_hz=0)
    assert not off["run_at_walking_cadence"].any()


def test_cli_predict_says_which_windows_the_rule_moved(demo, slowed_run, tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv

    path = tmp_path / "slowed.csv"
    write_gaitml_csv(slowed_run, path)
    assert main(["predict", str(DEMO), str(path), "--json", "--run-cadence", "on"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    n = out["run_at_walking_cadence_count"]
    assert n >= 10 and sum(w["run_at_walking_cadence"] for w in out["windows"]) == n
    assert out["run_cadence"] == {"min_cadence_hz": RUN_MIN_CADENCE_HZ}
    assert out["counts"].get("run", 0) + n <= len(out["windows"])
    line = [ln for ln in cap.err.splitlines() if "walking step cadence" in ln]
    # the line counts the moved windows answered in domain (the domain warning speaks for the others)
    n_in = sum(w["run_at_walking_cadence"] and w["in_domain"] is not False for w in out["windows"])
    assert n_in >= 1
    assert len(line) == 1 and line[0].startswith(f"gaitml: warning: {n_in} of ") and "mode_raw keeps" in line[0]
    assert main(["predict", str(DEMO), str(path), "--json", "--run-cadence", "off"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["run_at_walking_cadence_count"] == 0 and out["run_cadence"] == {"min_cadence_hz": None}
    assert main(["predict", str(DEMO), str(path), "--run-cadence", "fast"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--run-cadence 'fast'" in err[0]


def test_pdr_with_a_model_reads_the_moved_windows(demo, slowed_run):
    from gaitml.pdr import run_pdr

    rec = slowed_run
    steps = {}
    for name, hz in (("on", RUN_MIN_CADENCE_HZ), ("off", 0)):
        res = run_pdr(rec, model=demo, modes="model", detector="adaptive", run_min_cadence_hz=hz)
        steps[name] = res.steps["mode"].astype(str).to_numpy()
    assert len(steps["on"]) == len(steps["off"]) > 20
    assert (steps["off"] == "run").sum() - (steps["on"] == "run").sum() >= 5
