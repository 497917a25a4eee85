"""Per-step modes from window predictions and the mode-boundary refinement (gaitml.pdr.step_modes)."""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.models import LinearOVOSVM
from gaitml.pdr.step_modes import mode_runs, pair_margin, refine_mode_boundaries
from gaitml.recording import Recording

FS = 50.0
ROOT = Path(__file__).resolve().parents[2]


class SignOfMeanX:
    """A two-class 'model' whose evidence for A is the mean of acc x over the window (feature 0)."""

    classes_ = np.array(["A", "B"])

    def predict_proba(self, X):
        z = 4.0 * np.asarray(X)[:, 0]
        p = 1.0 / (1.0 + np.exp(-z))
        return np.c_[p, 1.0 - p]

    def predict(self, X):
        return np.where(np.asarray(X)[:, 0] > 0, "A", "B")


def fake_model(estimator=None, input_kind="features"):
    return SimpleNamespace(
        estimator=estimator or SignOfMeanX(),
        sampling_rate_hz=FS,
        length_s=1.5,
        input_kind=input_kind,
        feature_set="all52",
        raw_channels=["acc_x", "acc_y", "acc_z"],
        labels=["A", "B"],
    )


def two_mode_recording(change_s: float, duration_s: float = 12.0) -> Recording:
    """acc x = +1 before ``change_s`` (mode A) and -1 after it (mode B), gravity on z."""
    t = np.arange(int(duration_s * FS)) / FS
    acc = np.zeros((len(t), 3))
    acc[:, 0] = np.where(t < change_s, 1.0, -1.0) + 0.05 * np.sin(2 * np.pi * 2.0 * t)
    acc[:, 2] = 9.81
    return Recording.from_arrays(acc, FS, gyr=np.zeros_like(acc))


def test_mode_runs():
    assert mode_runs(["a", "a", "b", "a"]) == [(0, 2, "a"), (2, 3, "b"), (3, 4, "a")]
    assert mode_runs([]) == []


@pytest.mark.parametrize("shift", [-3, -2, -1, 1, 2, 3])
def test_a_misplaced_change_moves_to_the_step_at_the_true_change(shift):
    steps = np.arange(0.5, 11.5, 0.5)
    change = 6.0  # a step peak: this step and the later ones are mode B
    rec = two_mode_recording(change)
    truth = np.where(steps < change, "A", "B")
    j = int(np.searchsorted(steps, change))
    initial = np.where(np.arange(len(steps)) < j + shift, "A", "B")
    out = refine_mode_boundaries(fake_model(), rec, steps, initial)
    assert out.tolist() == truth.tolist()


def test_a_short_third_mode_between_two_modes_is_a_transition_artefact():
    steps = np.arange(0.5, 11.5, 0.5)
    rec = two_mode_recording(6.0)
    est = SignOfMeanX()
    est.classes_ = np.array(["A", "B", "C"])
    proba = est.predict_proba

    def proba3(X):
        p = proba(X)
        return np.c_[p[:, 0], p[:, 1], np.full(len(p), 1e-6)]

    est.predict_proba = proba3
    model = fake_model(est)
    model.labels = ["A", "B", "C"]
    initial = np.array(["A"] * 10 + ["C", "C"] + ["B"] * 10)  # C covers 0.5 s < one window
    out = refine_mode_boundaries(model, rec, steps, initial)
    assert out.tolist() == ["A"] * 11 + ["B"] * 11
    # a third mode lasting longer than one window is a real segment: its boundaries may
    # move (here the evidence says A and B everywhere) but never past its middle
    long_c = np.array(["A"] * 6 + ["C"] * 6 + ["B"] * 10)
    out = refine_mode_boundaries(model, rec, steps, long_c)
    assert out.tolist() == ["A"] * 8 + ["C"] * 2 + ["B"] * 12


def test_nothing_to_refine_without_a_change():
    steps = np.arange(0.5, 11.5, 0.5)
    rec = two_mode_recording(6.0)
    same = np.array(["A"] * len(steps))
    assert refine_mode_boundaries(fake_model(), rec, steps, same).tolist() == same.tolist()
    assert refine_mode_boundaries(fake_model(), rec, steps[:1], same[:1]).tolist() == ["A"]


def test_refinement_with_a_raw_input_model_uses_full_windows():
    class RawMeanX(SignOfMeanX):
        def predict_proba(self, X):
            return super().predict_proba(np.asarray(X)[:, :, 0].mean(axis=1, keepdims=True))

    steps = np.arange(0.5, 11.5, 0.5)
    rec = two_mode_recording(6.0)
    initial = np.where(steps < 7.0, "A", "B")
    out = refine_mode_boundaries(fake_model(RawMeanX(), input_kind="raw"), rec, steps, initial)
    assert out.tolist() == np.where(steps < 6.0, "A", "B").tolist()


def test_pair_margin_of_the_linear_ovo_svm_is_the_pair_machine():
    rng = np.random.default_rng(0)
    X = np.r_[rng.normal(-2, 1, (60, 2)), rng.normal(2, 1, (60, 2)), rng.normal([2, -6], 1, (60, 2))]
    y = np.array(["a"] * 60 + ["b"] * 60 + ["c"] * 60)
    svm = LinearOVOSVM().fit(X, y)
    m_ab = pair_margin(svm, X, "a", "b")
    assert np.all(m_ab == -pair_margin(svm, X, "b", "a"))
    assert np.mean(m_ab[:60] > 0) > 0.95 and np.mean(m_ab[60:120] < 0) > 0.95
    with pytest.raises(InputError, match="classes of the model"):
        pair_margin(svm, X, "a", "z")


def test_pair_margin_falls_back_to_hard_predictions():
    class HardOnly:
        classes_ = np.array(["A", "B"])

        def predict(self, X):
            return np.where(np.asarray(X)[:, 0] > 0, "A", "B")

    assert pair_margin(HardOnly(), np.array([[1.0], [-1.0]]), "A", "B").tolist() == [1.0, -1.0]


def test_bad_input_is_refused():
    rec = two_mode_recording(6.0)
    with pytest.raises(InputError, match="one mode per step"):
        refine_mode_boundaries(fake_model(), rec, [1.0, 2.0], ["A"])
    with pytest.raises(InputError, match="increasing"):
        refine_mode_boundaries(fake_model(), rec, [2.0, 1.0], ["A", "B"])
    with pytest.raises(InputError, match="not classes of the model"):
        refine_mode_boundaries(fake_model(), rec, [1.0, 2.0], ["A", "run"])


@pytest.fixture(scope="module")
def hand_held_model(tmp_path_factory):
    """A hand-held simulator model: the earlier shipped demo's recipe (32 simulated subjects x 300 s, phone flat or
    tilted, five modes, linear OVO SVM on all52+gyro, seed 1000), trained without cross-validation (about 1 min).

    The refinement is a property of the boundary search, not of one shipped model: the test
    needs a model of the simulated hand-held walker it is scored on (the shipped default is
    also trained on real carried phones and reads simulated hand-held walking less well).
    """
    from gaitml.models import load_model
    from gaitml.pipeline.config import parse_config
    from gaitml.pipeline.runner import train_config

    cfg = parse_config(
        {
            "name": "hand-held",
            "seed": 1000,
            "data": {"source": "simulated", "simulated": {"subjects": 32, "pose": "mixed", "duration_s": 300.0}},
            "features": {"set": "all52+gyro"},
            "train": {"cross_validate": False, "domain_dynamics": False},
        }
    )
    out = tmp_path_factory.mktemp("hand-held")
    train_config(cfg, out_dir=out, progress=False)
    return load_model(out)


@pytest.mark.slow
def test_refinement_fixes_steps_at_mode_changes_of_a_simulated_walk(hand_held_model):
    """A hand-held simulator model, a walker it was not trained on (route seed 12; its training subjects are seed 1000's)."""
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    model = hand_held_model
    rec = simulate_route("straight", seed=12, duration_s=240.0)
    truth = run_pdr(rec, modes="true", heading="gyro", detector="single-peak").steps
    true_modes, t = truth["mode"].to_numpy(), truth["t_peak_s"].to_numpy()
    labels = rec.labels.astype(str)
    changes = np.flatnonzero(labels[1:] != labels[:-1]) / rec.sampling_rate_hz
    at_change = np.min(np.abs(t[:, None] - changes[None, :]), axis=1) < 0.8
    # the model's own per-step modes (issue 12: `mode` moves out-of-domain steps forward, `mode_model` keeps the model's)
    kw = {"model": model, "modes": "model", "heading": "gyro", "detector": "single-peak"}  # the steps of `truth`
    nearest = run_pdr(rec, **kw, mode_boundaries="nearest").steps["mode_model"].to_numpy()
    refined = run_pdr(rec, **kw).steps["mode_model"].to_numpy()
    wrong_nearest, wrong_refined = nearest != true_modes, refined != true_modes
    assert wrong_refined[at_change].sum() <= wrong_nearest[at_change].sum() / 2, (
        wrong_nearest[at_change].sum(),
        wrong_refined[at_change].sum(),
    )
    assert wrong_refined[~at_change].sum() <= wrong_nearest[~at_change].sum()
    assert 1 - wrong_refined.mean() >= 0.98


def test_more_input_checks():
    rec = two_mode_recording(6.0)
    with pytest.raises(InputError, match="finite"):
        refine_mode_boundaries(fake_model(), rec, [1.0, np.nan], ["A", "B"])
    with pytest.raises(InputError, match="not classes of the model"):
        refine_mode_boundaries(fake_model(), rec, [1.0], ["run"])
    with pytest.raises(InputError, match="search_s"):
        refine_mode_boundaries(fake_model(), rec, [1.0, 2.0], ["A", "B"], search_s=-1)
    with pytest.raises(InputError, match="raw-input model"):
        refine_mode_boundaries(fake_model(input_kind="raw"), rec, [1.0, 2.0], ["A", "B"], short_window_s=0.5)
    with pytest.raises(InputError, match="shorter than the evidence window"):
        refine_mode_boundaries(fake_model(), rec.slice(0, 30), [0.1, 0.3], ["A", "B"])


def test_two_adjacent_artefacts_both_go():
    """A, C, D, B with C and D each shorter than a window: the later one must not take C's mode."""
    steps = np.arange(0.5, 11.5, 0.5)
    rec = two_mode_recording(6.0)
    est = SignOfMeanX()
    est.classes_ = np.array(["A", "B", "C", "D"])
    proba = est.predict_proba
    est.predict_proba = lambda X: np.c_[proba(X), np.full((len(X), 2), 1e-6)]
    model = fake_model(est)
    model.labels = ["A", "B", "C", "D"]
    initial = np.array(["A"] * 10 + ["C", "D"] + ["B"] * 10)
    out = refine_mode_boundaries(model, rec, steps, initial)
    assert out.tolist() == ["A"] * 11 + ["B"] * 11


def test_run_pdr_mode_boundaries_options_and_cli(tmp_path, capsys):
    import json

    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    if not (ROOT / "models" / "demo" / "model.json").is_file():
        pytest.skip("models/demo is not trained")
    from gaitml.models import load_model

    model = load_model(ROOT / "models" / "demo")
    rec = simulate_route("straight", seed=13, duration_s=40.0)
    with pytest.raises(InputError, match="mode_boundaries"):
        run_pdr(rec, model=model, modes="model", mode_boundaries="guess")
    assert run_pdr(rec, model=model, modes="model").info["mode_boundaries"] == "refine"  # single-peak: peaks
    fsm = run_pdr(rec, model=model, modes="model", detector="ifsm")
    assert fsm.info["mode_boundaries"] == "nearest" and any("not peaks" in n for n in fsm.info["notes"])
    assert run_pdr(rec, model=model, modes="model", detector="ifsm", mode_boundaries="refine").info["mode_boundaries"] == "refine"
    assert run_pdr(rec, modes="true").info["mode_boundaries"] is None
    # middle: the window nearest the middle between a step and the next one
    from gaitml.models import predict_recording
    from gaitml.pdr.step_modes import modes_from_windows

    mid = run_pdr(rec, model=model, modes="model", mode_boundaries="middle")
    t = mid.steps["t_peak_s"].to_numpy()
    t_mid = 0.5 * (t + np.r_[t[1:], t[-1] + np.median(np.diff(t))])
    assert mid.info["mode_boundaries"] == "middle"
    assert mid.steps["mode"].tolist() == modes_from_windows(predict_recording(model, rec), t_mid).tolist()
    path = tmp_path / "walk.csv"
    write_gaitml_csv(rec, path)
    capsys.readouterr()
    outs = {}
    for mb in ("nearest", "refine"):
        assert main(["pdr", str(path), "--model", str(ROOT / "models" / "demo"), "--mode-boundaries", mb, "--json"]) == 0
        outs[mb] = json.loads(capsys.readouterr().out)
    assert len(outs["nearest"]["trajectory"]) == len(outs["refine"]["trajectory"])


def test_an_unsorted_step_table_is_sorted_with_a_note():
    from gaitml.pdr import run_pdr
    from gaitml.steps import get_detector
    from tests.pdr.synth import synth_walk

    rec = synth_walk([("walk", 12, 0.0)], pitch_deg=10, noise=0.02)
    det = get_detector("single-peak")
    det.detect(rec)
    steps = det.steps_
    shuffled = steps.iloc[::-1]
    shuffled.attrs.update(steps.attrs)
    a = run_pdr(rec, steps=steps, modes="true", heading="gyro")
    b = run_pdr(rec, steps=shuffled, modes="true", heading="gyro")
    assert np.allclose(a.trajectory[["x_m", "y_m"]], b.trajectory[["x_m", "y_m"]])
    assert any("not in time order" in n for n in b.info["notes"])


def test_a_step_in_a_still_window_takes_the_models_own_answer():
    """A detected step is gait: the still gate of its window gives way to the model's answer (mode_raw)."""
    import pandas as pd

    from gaitml.pdr.step_modes import modes_from_windows

    windows = pd.DataFrame(
        {
            "t_start_s": [0.0, 1.0, 2.0],
            "t_end_s": [1.5, 2.5, 3.5],
            "mode": ["walk", "still", "backward"],
            "mode_raw": ["walk", "side_left", "backward"],
            "still": [False, True, False],
        }
    )
    modes = modes_from_windows(windows, [0.5, 1.75, 2.9])
    assert modes.tolist() == ["walk", "side_left", "backward"]
    assert "still" not in modes_from_windows(windows.drop(columns="mode_raw").assign(mode=["walk", "walk", "run"]), [1.75])


def test_side_steps_of_unsure_direction_walk_forward_and_are_counted(tmp_path, capsys):
    """The default model cannot tell left from right in a pocket: such side steps move forward, counted and warned."""
    import json
    from pathlib import Path

    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv
    from gaitml.models import load_model
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    model_dir = Path(__file__).resolve().parents[2] / "models" / "demo"
    model = load_model(model_dir)
    pocket = simulate_route("rectangle", seed=3, position="back-pocket")
    res = run_pdr(pocket, model=model, modes="model")
    side = res.steps["mode_model"].str.startswith("side_")
    assert side.sum() > 0 and res.info["side_direction_unsure_steps"] > 0
    moved = side & (res.steps["mode"] == "walk") & res.steps["in_domain"].astype(bool)
    assert res.info["side_direction_unsure_steps"] == int(moved.sum())
    assert not (res.steps["mode"].str.startswith("side_") & ~res.steps["mode_model"].str.startswith("side_")).any()
    hand = run_pdr(simulate_route("rectangle", seed=3, position="hand-flat"), model=model, modes="model")
    assert hand.info["side_direction_unsure_steps"] == 0 and hand.steps["mode"].str.startswith("side_").any()

    path = write_gaitml_csv(pocket, tmp_path / "pocket.csv")
    assert main(["pdr", str(path), "--model", str(model_dir), "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["side_direction_unsure_steps"] > 0
    assert cap.err.count("side steps of unsure direction") == 1


def test_foot_mounted_steps_is_reported_only_where_the_foot_rule_ran():
    import dataclasses

    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    if not (ROOT / "models" / "demo" / "model.json").is_file():
        pytest.skip("models/demo is not trained")
    from gaitml.models import load_model

    model = load_model(ROOT / "models" / "demo")
    rec = simulate_route("straight", seed=13, duration_s=30.0)
    ran = run_pdr(rec, model=model, modes="model")
    assert isinstance(ran.info["foot_mounted_steps"], int)
    assert ran.to_json_dict()["foot_mounted_steps"] == ran.info["foot_mounted_steps"]
    foot_trained = dataclasses.replace(model, domain=dataclasses.replace(model.domain, positions={**model.domain.positions, "foot": 1}))
    for m in (dataclasses.replace(model, domain=None), foot_trained):  # the rule is not checked: no count, not 0
        res = run_pdr(rec, model=m, modes="model")
        assert "foot_mounted_steps" not in res.info
        assert "foot_mounted_steps" not in res.to_json_dict()


def test_out_of_domain_reason_is_unknown_where_in_domain_is():
    """A model without a domain record checks nothing: every window and step has ``in_domain`` None and
    ``out_of_domain_reason`` None (unknown), in ``predict_recording``'s table, ``run_pdr``'s step table and
    the pdr JSON rows; a model with one gives the empty reason exactly where ``in_domain`` is True."""
    import dataclasses

    from gaitml.models import load_model, predict_recording
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    if not (ROOT / "models" / "demo" / "model.json").is_file():
        pytest.skip("models/demo is not trained")
    model = load_model(ROOT / "models" / "demo")
    rec = simulate_route("straight", seed=13, duration_s=30.0)
    bare = dataclasses.replace(model, domain=None)

    table = predict_recording(bare, rec)
    assert all(v is None for v in table["in_domain"]) and all(r is None for r in table["out_of_domain_reason"])
    res = run_pdr(rec, model=bare, modes="model")
    assert res.n_steps > 0
    assert all(v is None for v in res.steps["in_domain"])
    assert all(r is None for r in res.steps["out_of_domain_reason"])
    rows = res.to_json_dict()["trajectory"]
    assert all(row["in_domain"] is None and row["out_of_domain_reason"] is None for row in rows)

    checked = run_pdr(rec, model=model, modes="model")
    flags = checked.steps["in_domain"].tolist()
    reasons = checked.steps["out_of_domain_reason"].tolist()
    assert all(v is not None for v in flags)
    assert all((r == "") == bool(v) for r, v in zip(reasons, flags, strict=True))
    rows = checked.to_json_dict()["trajectory"]
    assert rows[0]["in_domain"] is None and rows[0]["out_of_domain_reason"] is None
    assert all((row["out_of_domain_reason"] is None) == row["in_domain"] for row in rows[1:])
