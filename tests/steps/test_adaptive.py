"""The `adaptive` step detector (gaitml.steps.adaptive): steps not strides, confidence, cadence, its held-out figures on
the Oxford step-counter recordings, and the step counts of every paper detector on the IFSM recordings against the truth."""

from __future__ import annotations

import io
import json
from contextlib import redirect_stderr, redirect_stdout
from typing import ClassVar

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.pipeline.steps_real import TUNED_SUFFIX, holdout_folds, run_steps_real, tuned_evaluation
from gaitml.recording import Recording
from gaitml.steps import AdaptiveStepDetector, BaseStepDetector, get_detector, make_step_table
from gaitml.steps._base import count_accuracy
from gaitml.steps.adaptive import fold_steps
from tests.conftest import shared
from tests.steps.conftest import synthetic_walk


def one_leg_walk(n_strides=60, stride_s=1.1, fs=100.0, far=0.3, swing=2.0, noise_ms2=0.05, seed=0) -> Recording:
    """A pocket phone that sees one leg: a thigh swing once per stride, a heel strike of the near leg and a weaker
    one (``far`` times as strong) of the other leg half a stride later; the true steps are both strikes."""
    rng = np.random.default_rng(seed)
    lead = 2.0
    n = int((2 * lead + n_strides * stride_s) * fs)
    t = np.arange(n) / fs
    tw = t - lead
    walking = (tw >= 0) & (tw < n_strides * stride_s)
    z = np.where(walking, swing * np.sin(2 * np.pi * tw / stride_s), 0.0)
    true = []
    for k in range(n_strides):
        for offset, amp in ((0.0, 3.0), (0.5, 3.0 * far)):
            tc = lead + (k + offset) * stride_s
            true.append(tc)
            z += amp * np.exp(-0.5 * ((t - tc) / 0.04) ** 2)
    acc = np.column_stack([rng.normal(0, noise_ms2, n), rng.normal(0, noise_ms2, n), 9.80665 + z + rng.normal(0, noise_ms2, n)])
    return Recording.from_arrays(acc, fs, reference={"steps_t_s": np.sort(true), "n_steps_true": 2 * n_strides})


# -- stride versus step --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "stride_s, far, swing",
    # issue 30: a stride of 0.83-1.33 s without half-period evidence is a stride only with more motion than a slow
    # walker makes (band RMS > 1.5 m/s^2, real pockets 1.8-3.9): those cases swing 3 m/s^2 (was 2, RMS ~1.4,
    # which is now read as a slow walker's step)
    [(0.9, 0.3, 3.0), (1.1, 0.3, 3.0), (1.1, 0.15, 4.0), (1.3, 0.5, 4.0), (1.5, 0.3, 2.0), (1.5, 0.5, 0.0), (1.1, 0.0, 3.0)],
)
def test_one_leg_signal_counts_steps_not_strides(stride_s, far, swing):
    rec = one_leg_walk(stride_s=stride_s, far=far, swing=swing)
    det = AdaptiveStepDetector().detect(rec)
    assert abs(len(det.steps_) - 120) <= 2, len(det.steps_)
    # the cadence is the step cadence (two per stride), and the windows know they saw strides
    walking = det.cadence_[(det.cadence_["t_s"] > 5) & (det.cadence_["t_s"] < 60)]
    np.testing.assert_allclose(walking["cadence_hz"], 2.0 / stride_s, rtol=0.05)
    assert walking["stride"].all()


def test_two_legs_alike_are_steps_not_half_steps():
    rec = synthetic_walk(n_steps=60, step_period_s=0.75, fs=100.0)  # 1.33 Hz: a slow walk, its half would be running
    det = AdaptiveStepDetector().detect(rec)
    assert abs(len(det.steps_) - 60) <= 1
    walking = det.cadence_[(det.cadence_["t_s"] > 5) & (det.cadence_["t_s"] < 40)]
    np.testing.assert_allclose(walking["cadence_hz"], 1 / 0.75, rtol=0.03)
    assert not walking["stride"].any()


@pytest.mark.parametrize("step_period_s", [0.3, 0.4, 0.8])
def test_cadence_range_ends(step_period_s):
    """Running at 3.3 steps/s and a slow walk at 1.25 steps/s: steps, not half or double steps."""
    rec = synthetic_walk(n_steps=100, step_period_s=step_period_s, fs=100.0)
    assert abs(len(AdaptiveStepDetector().detect(rec).steps_) - 100) <= 1


def test_fold_cancels_the_stride_and_keeps_the_step():
    T = 50
    t = np.arange(2000)
    stride = np.sin(2 * np.pi * t / (2 * T))
    step = np.sin(2 * np.pi * t / T)
    inner = slice(200, 1800)
    np.testing.assert_allclose(fold_steps(stride, np.full(len(t), T))[inner], 0.0, atol=1e-9)
    np.testing.assert_allclose(fold_steps(step, np.full(len(t), T))[inner], step[inner], atol=1e-9)


def test_confidence_and_cadence_columns():
    rec = synthetic_walk(n_steps=40, fs=100.0)
    det = AdaptiveStepDetector().detect(rec)
    st = det.steps_
    assert {"start", "peak", "end", "t_start_s", "t_peak_s", "t_end_s", "period_s", "correlation"} <= set(st.columns)
    assert {"cadence_hz", "confidence"} <= set(st.columns)
    assert ((st["confidence"] >= 0) & (st["confidence"] <= 1)).all()
    assert st["confidence"].median() > 0.8  # a clean periodic walk
    np.testing.assert_allclose(st["cadence_hz"], 1 / st["period_s"])
    assert list(det.cadence_.columns) == ["t_s", "cadence_hz", "period_s", "periodicity", "stride", "inferred", "gyro", "swing"]
    # dropping low-confidence steps only removes steps
    kept = AdaptiveStepDetector(min_confidence=0.99).detect(rec).steps_
    assert set(kept["peak"]) <= set(st["peak"]) and len(kept) < len(st)


def test_bad_adaptive_parameters():
    rec = synthetic_walk(n_steps=20, fs=100.0)
    with pytest.raises(InputError, match="min_step_hz"):
        AdaptiveStepDetector(min_step_hz=3.0, max_step_hz=2.0).detect(rec)
    with pytest.raises(InputError, match="band_hz"):
        AdaptiveStepDetector(band_hz=(0.5, 80.0)).detect(rec)
    with pytest.raises(InputError, match="fold"):
        AdaptiveStepDetector(fold="yes").detect(rec)
    with pytest.raises(InputError, match="edge_confidence_ratio"):
        AdaptiveStepDetector(edge_confidence_ratio=1.5).detect(rec)
    for bad in (0, 2.5):
        with pytest.raises(InputError, match="min_bout_steps"):
            AdaptiveStepDetector(min_bout_steps=bad).detect(rec)


# -- walking bouts (stage 5) -----------------------------------------------------------------------------------


def bout_walks(n_bouts=3, n_steps=30, step_period_s=0.55, pause_s=6.0, fs=100.0, handling=False, seed=0) -> Recording:
    """Walks of ``n_steps`` steps with still pauses between them; with ``handling`` each pause holds four bumps at
    random times and widths (the phone picked up, tapped, put away), which are not steps."""
    rng = np.random.default_rng(seed)
    parts, true, t0 = [], [], 0.0
    n_pause = int(pause_s * fs)
    tt = np.arange(n_pause) / fs
    for _ in range(n_bouts):
        pause = np.zeros(n_pause)
        if handling:
            for c in rng.uniform(0.5, pause_s - 0.5, 4):
                pause += rng.uniform(1, 3) * np.exp(-0.5 * ((tt - c) / rng.uniform(0.05, 0.15)) ** 2)
        parts.append(pause)
        t0 += pause_s
        n_walk = int(round(n_steps * step_period_s * fs))
        parts.append(3.0 * np.sin(2 * np.pi * np.arange(n_walk) / fs / step_period_s))
        true.extend(t0 + (np.arange(n_steps) + 0.25) * step_period_s)
        t0 += n_walk / fs
    parts.append(np.zeros(n_pause))
    z = np.concatenate(parts) + 9.80665
    n = len(z)
    acc = np.column_stack([rng.normal(0, 0.05, n), rng.normal(0, 0.05, n), z + rng.normal(0, 0.05, n)])
    return Recording.from_arrays(acc, fs, reference={"steps_t_s": np.array(true), "n_steps_true": len(true)})


def test_bout_edge_keep_trims_only_the_weak_fringe():
    from gaitml.steps.adaptive import bout_edge_keep

    bout = np.array([0] * 8 + [1] * 4)
    conf = np.array([0.1, 0.2, 0.9, 0.9, 0.05, 0.9, 0.9, 0.2] + [0.4] * 4)
    # bout 0: median 0.55, so edges under 0.275 go; the weak step inside stays. Bout 1 (a one-leg bout whose
    # confidence is halved throughout) is judged against its own median and kept whole.
    keep = bout_edge_keep(bout, conf, 0.5)
    assert keep.tolist() == [False, False, True, True, True, True, True, False] + [True] * 4
    assert bout_edge_keep(bout, conf, 0.0).all()
    # the vectorised rule against a loop over bouts
    rng = np.random.default_rng(3)
    bout = np.sort(rng.integers(0, 40, 400))
    conf = rng.uniform(0, 1, 400) ** 2
    ref = np.ones(400, dtype=bool)
    for b in np.unique(bout):
        i = np.flatnonzero(bout == b)
        strong = i[conf[i] >= 0.5 * np.median(conf[i])]
        ref[i[(i < strong[0]) | (i > strong[-1])]] = False
    np.testing.assert_array_equal(bout_edge_keep(bout, conf, 0.5), ref)


def test_a_pause_between_bouts_costs_no_step():
    """The steps beside a pause keep their timing evidence (their regularity comes from intervals inside the bout)."""
    rec = bout_walks()
    st = AdaptiveStepDetector().detect(rec).steps_
    assert len(st) == 90
    assert len(AdaptiveStepDetector(edge_confidence_ratio=0.0, min_bout_steps=1).detect(rec).steps_) == 90
    t = st["t_peak_s"].to_numpy()
    edges = np.r_[0, np.flatnonzero(np.diff(t) > 2 * 0.55) + 1]
    assert len(edges) == 3 and (st["confidence"].to_numpy()[edges] > 0.7).all()


@pytest.mark.parametrize("seed", range(4))
def test_bout_rules_drop_handling_between_walks(seed):
    """Bumps between walks (not steps): the bout rules drop most of what the peak picker finds there (measured with the
    rules 97 / 92 / 96 / 96 of 90 steps for seeds 0-3, without them 103 / 102 / 106 / 105)."""
    rec = bout_walks(handling=True, seed=seed)
    with_rules = len(AdaptiveStepDetector().detect(rec).steps_)
    without = len(AdaptiveStepDetector(edge_confidence_ratio=0.0, min_bout_steps=1).detect(rec).steps_)
    assert 90 <= with_rules < without
    assert with_rules - 90 <= 8


def _cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def test_steps_json_carries_cadence_and_confidence(tmp_path):
    rec = synthetic_walk(n_steps=30, fs=50.0)
    path = tmp_path / "walk.csv"
    t = np.arange(rec.n_samples) / rec.sampling_rate_hz
    pd.DataFrame({"t": t, "acc_x": rec.acc[:, 0], "acc_y": rec.acc[:, 1], "acc_z": rec.acc[:, 2]}).to_csv(path, index=False)
    rc, out, err = _cli(["steps", str(path), "--detector", "adaptive", "--json"])
    assert rc == 0, err
    obj = json.loads(out)
    assert abs(obj["n_steps"] - 30) <= 1
    assert set(obj["steps"][0]) == {"t_s", "period_s", "cadence_hz", "confidence", "confident"}
    assert all(0 <= s["confidence"] <= 1 for s in obj["steps"])
    assert obj["cadence"] and set(obj["cadence"][0]) == {"t_s", "cadence_hz", "periodicity", "stride"}
    # a paper detector keeps the old contract
    rc, out, _ = _cli(["steps", str(path), "--detector", "single-peak", "--json"])
    obj = json.loads(out)
    assert set(obj["steps"][0]) == {"t_s", "period_s"} and "cadence" not in obj
    rc, out, _ = _cli(["steps", str(path), "--detector", "adaptive"])
    assert "step confidence: median" in out


# -- held-out evaluation -------------------------------------------------------------------------------------


def _fake_oxford(user, position, surface="Hard", n_true=100, rate=1.0, i=0) -> Recording:
    acc = np.tile([0.0, 0.0, 9.80665], (300, 1))
    meta = {
        "format": "oxford",
        "user": user,
        "position": position,
        "surface": surface,
        "id": f"{user}_{surface}_{position}_{i}",
        "rate": rate,
    }
    return Recording.from_arrays(acc, 100.0, meta=meta, reference={"n_steps_true": n_true})


class FakeTunable(BaseStepDetector):
    """A detector whose count is ``gain * rate * 100`` (``rate`` from the recording's meta): the best gain is 1 / rate.

    Parameters
    ----------
    gain : float, default 1.0
    """

    name = "fake-tunable"
    param_grid: ClassVar[dict[str, tuple]] = {"gain": (0.5, 1.0, 2.0)}

    def __init__(self, *, gain: float = 1.0):
        self.gain = gain

    def detect(self, recording):
        n = int(round(self.gain * recording.meta["rate"] * 100))
        idx = np.arange(n) % recording.n_samples
        self.steps_ = make_step_table(idx, idx, idx, recording.sampling_rate_hz, event="t_peak_s")
        return self


def _fake_set():
    recs = []
    for u, rate in (("A", 1.0), ("B", 0.5), ("C", 0.5)):
        for pos in ("InHand", "BackPocket"):
            recs.append(_fake_oxford(u, pos, rate=rate))
    recs.append(_fake_oxford("A", "InHand", surface="Carpet", rate=1.0, i=1))
    recs.append(
        Recording.from_arrays(
            np.tile([0.0, 0.0, 9.8], (300, 1)), 50.0, meta={"format": "ifsm-xlsx", "rate": 1.0}, reference={"n_steps_true": 100}
        )
    )
    return recs


@pytest.mark.parametrize("scheme, key", [("user", "user"), ("position", "position")])
def test_holdout_folds_never_share_a_group(scheme, key):
    recs = _fake_set()
    folds = holdout_folds(recs, scheme)
    seen = []
    for value, train, test in folds:
        assert test and train
        assert {recs[i].meta[key] for i in test} == {value}
        assert value not in {recs[i].meta[key] for i in train}
        assert all(recs[i].meta["surface"] == "Hard" for i in train)  # carpet is scored, never tuned on
        seen.extend(test)
    oxford = [i for i, r in enumerate(recs) if r.meta.get("format") == "oxford"]
    assert sorted(seen) == oxford  # every Oxford recording is held out exactly once; the IFSM one never
    with pytest.raises(InputError, match="unknown held-out scheme"):
        holdout_folds(recs, "phone")


def test_tuned_setting_depends_only_on_the_training_users(monkeypatch):
    from gaitml.steps import _registry

    monkeypatch.setitem(_registry.DETECTORS, "fake-tunable", FakeTunable)
    recs = _fake_set()
    in_rows, held, chosen = tuned_evaluation(recs, "fake-tunable", ("user",))
    # users B and C need gain 2, user A gain 1: without A the training users choose 2, and A's held-out rows pay for it
    assert chosen["user"] == {"A": {"gain": 2.0}, "B": {"gain": 1.0}, "C": {"gain": 1.0}}
    rows_a = [r for r in held["user"] if r["fold"] == "A"]
    assert rows_a and all(r["count_accuracy"] == pytest.approx(0.0) for r in rows_a)
    assert all(r["detector"] == "fake-tunable" + TUNED_SUFFIX for r in in_rows)
    # brute force: each fold's choice is the best mean count accuracy over its training recordings only
    for value, train, _ in holdout_folds(recs, "user"):

        def score(g, train=train):
            return np.mean([count_accuracy(g * recs[i].meta["rate"] * 100, 100) for i in train])

        best = max((0.5, 1.0, 2.0), key=lambda g: (score(g), -[0.5, 1.0, 2.0].index(g)))
        assert chosen["user"][value] == {"gain": best}
    # changing the held-out user's data (its true counts) leaves that fold's choice unchanged
    for r in recs:
        if r.meta.get("user") == "A":
            r.reference["n_steps_true"] = 50
    _, _, chosen2 = tuned_evaluation(recs, "fake-tunable", ("user",))
    assert chosen2["user"]["A"] == chosen["user"]["A"]


def test_run_writes_side_by_side_tables(monkeypatch, tmp_path):
    from gaitml.steps import _registry

    monkeypatch.setitem(_registry.DETECTORS, "fake-tunable", FakeTunable)
    recs = _fake_set()[:-1]
    summary = run_steps_real(tmp_path / "run", data_dir=tmp_path, detectors=["fake-tunable"], recordings=recs, holdout=["user", "position"])
    assert summary["fitted"] == ["fake-tunable" + TUNED_SUFFIX]
    by_pos = pd.read_csv(tmp_path / "run" / "oxford_by_position.csv")
    assert {"heldout_user_count_accuracy", "heldout_position_count_accuracy"} <= set(by_pos.columns)
    as_is = by_pos[by_pos["detector"] == "fake-tunable"]
    np.testing.assert_allclose(as_is["count_accuracy"], as_is["heldout_user_count_accuracy"])  # nothing fitted: the same
    tuned = summary["oxford"]["fake-tunable" + TUNED_SUFFIX]["Hard"]
    assert tuned["heldout_user_mean_count_accuracy"] < tuned["mean_count_accuracy"]  # the in-sample choice flatters
    report = (tmp_path / "run" / "report.md").read_text()
    assert "in sample vs leave-one-user-out" in report and "in sample vs leave-one-position-out" in report
    assert "without user A" in report
    held = pd.read_csv(tmp_path / "run" / "heldout_per_recording.csv")
    assert set(held["holdout"]) == {"user", "position"}


def test_config_holdout_keys(tmp_path):
    from gaitml.errors import ConfigError
    from gaitml.pipeline import parse_config

    base = {"name": "s", "task": "steps", "data": {"path": str(tmp_path)}}
    cfg = parse_config(base)
    assert cfg["evaluation"] == {"holdout": "user", "tune": True}
    cfg = parse_config({**base, "evaluation": {"holdout": ["user", "position"], "tune": False}})
    assert cfg["evaluation"]["holdout"] == ["user", "position"]
    for bad, match in (("phone", "not allowed"), (["none", "user"], "mixes 'none'"), ([], "at least one"), (3, "wrong type")):
        with pytest.raises(ConfigError, match=match):
            parse_config({**base, "evaluation": {"holdout": bad}})


# -- real data -----------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def oxford_recs():
    from gaitml.io import read_recording
    from gaitml.io.oxford import list_oxford_folders

    return [read_recording(f) for f in list_oxford_folders(shared("oxford-step-counter", "optimisation"))]


def _by_position(rows) -> pd.Series:
    df = pd.DataFrame(rows)
    return df[df["surface"] == "Hard"].groupby("position")["count_accuracy"].mean()


def test_adaptive_held_out_user_figures(oxford_recs, tmp_path):
    """Held-out user count accuracy on hard floors and carpet, overall and in every position, above floors set a margin
    below the figures of experiments/reports/steps-heldout.md (the defaults are not chosen on these recordings)."""
    summary = run_steps_real(tmp_path / "run", data_dir=tmp_path, detectors=["adaptive"], recordings=oxford_recs, tune=False)
    hard = summary["oxford"]["adaptive"]["Hard"]
    assert hard["heldout_user_mean_count_accuracy"] >= 0.975
    assert hard["heldout_user_worst_position_count_accuracy"] >= 0.945
    assert summary["oxford"]["adaptive"]["Carpet"]["heldout_user_mean_count_accuracy"] >= 0.98
    pos = hard["by_position"]
    for p, v in pos.items():
        assert v["heldout_user_count_accuracy"] >= 0.945, p
    assert pos["BackPocket"]["heldout_user_count_accuracy"] >= 0.955  # the position of the issue (old: strides elsewhere)
    assert pos["NeckPouch"]["heldout_user_count_accuracy"] >= 0.982


@pytest.mark.slow
def test_adaptive_tuned_held_out(oxford_recs):
    """The grid variant chosen on training users only, scored on the left-out user: above the same floors."""
    _, held, chosen = tuned_evaluation(oxford_recs, "adaptive", ("user",))
    acc = _by_position(held["user"])
    assert acc.mean() >= 0.972 and acc.min() >= 0.945
    assert set(chosen["user"]) == {"Jamie", "Carmelo", "Dario"}


#: True step counts of the two IFSM recordings (paper 000, annotated in ../shared/data/ifsm-flat-phone).
IFSM_TRUE_STEPS = (284, 319)


def test_adaptive_ifsm_within_one_percent(ifsm_recs):
    counts = [len(get_detector("adaptive").detect(r).steps_) for r in ifsm_recs]
    assert all(count_accuracy(n, true) >= 0.99 for n, true in zip(counts, IFSM_TRUE_STEPS, strict=True)), counts


def test_window_autocorrelation_matches_a_direct_loop():
    from gaitml.steps.adaptive import window_autocorrelation

    rng = np.random.default_rng(1)
    y = np.cumsum(rng.normal(size=1500)) * 0.1 + np.sin(np.arange(1500) / 4) + 5
    L, H, lags = 125, 25, np.arange(6, 44)
    r = window_autocorrelation(y, L, H, lags)
    for i in (0, 17, (len(y) - L) // H):
        w = y[i * H : i * H + L] - y[i * H : i * H + L].mean()
        ref = [(w[: L - k] @ w[k:]) / np.sqrt((w[: L - k] @ w[: L - k]) * (w[k:] @ w[k:])) for k in lags]
        np.testing.assert_allclose(r[i], ref, atol=1e-12)
    # a periodic signal correlates as well at two periods as at one (no decay with the lag)
    p = window_autocorrelation(np.sin(2 * np.pi * np.arange(500) / 20), 125, 25, np.array([20, 40]))
    np.testing.assert_allclose(p, 1.0, atol=1e-9)


#: Count accuracy floors of the paper detectors on the two IFSM recordings against IFSM_TRUE_STEPS, 1-2 points below
#: the figures of experiments/reports/steps-heldout.md (single-peak, ifsm, adfsm, autocorr: 98.7-100 %; fsm-selflearn
#: 98.2 / 99.4 %; ifsm-literal, the paper's thresholds read literally, 76.8 / 90.6 %), so a better count passes.
PAPER_IFSM_FLOORS = {
    "single-peak": (0.985, 0.985),
    "ifsm": (0.985, 0.985),
    "ifsm-literal": (0.75, 0.89),
    "adfsm": (0.985, 0.97),
    "autocorr": (0.98, 0.98),
    "fsm-selflearn": (0.965, 0.98),
}


@pytest.mark.parametrize("name", sorted(PAPER_IFSM_FLOORS))
def test_paper_detectors_count_the_ifsm_steps(ifsm_recs, name):
    counts = [len(get_detector(name).detect(r).steps_) for r in ifsm_recs]
    for n, true, floor in zip(counts, IFSM_TRUE_STEPS, PAPER_IFSM_FLOORS[name], strict=True):
        assert count_accuracy(n, true) >= floor, (name, counts)


def test_a_step_found_alone_has_no_timing_evidence_and_confidence_zero():
    """The only step of a short signal is alone in its bout: confidence 0, as for a lone step inside a longer one."""
    from gaitml.simulate import sample_subjects, simulate_recording
    from gaitml.steps.adaptive import adaptive_steps

    rec = simulate_recording(sample_subjects(1, seed=1)[0], duration_s=30, seed=1, modes=("walk",))
    mag = np.linalg.norm(rec.acc, axis=1)
    found = 0
    for length in range(90, 200, 3):
        r = adaptive_steps(mag[200 : 200 + length], 50.0, min_bout_steps=1, edge_confidence_ratio=0.0)
        if len(r["peak"]) == 1:
            found += 1
            assert r["confidence"][0] == 0.0
    assert found  # the case is exercised
