"""``gaitml pdr --model`` runs the still gate's step veto only when it can change a step's mode.

A step whose window the gate reads still takes the model's raw answer (``modes_from_windows``); a vetoed window keeps
its corrected mode, which the run-cadence rule and the side-direction check then read. So the veto matters to the PDR
only where a still-read window's corrected mode differs from its raw answer or that answer is run or a side step
(``veto_can_change_step_modes``); elsewhere its step finder is skipped and every step takes the same mode.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import gaitml.models._predict as P
from gaitml.models import load_model, predict_recording
from gaitml.pdr import run_pdr
from gaitml.pdr.step_modes import modes_from_windows
from gaitml.postprocess import adjacent_window_correction
from tests.conftest import ROOT
from tests.models.test_still_veto_swing import ear_walk


@pytest.fixture(scope="module")
def demo():
    return load_model(ROOT / "models" / "demo")


def test_the_veto_can_change_a_step_only_through_the_correction_a_run_or_a_side_step():
    still = np.array([True, True, False])
    assert not P.veto_can_change_step_modes(still, ["walk", "walk", "run"], ["walk", "walk", "side_left"])  # moving: not read
    assert P.veto_can_change_step_modes(still, ["walk", "backward", "walk"], ["walk", "walk", "walk"])  # the correction
    assert P.veto_can_change_step_modes(still, ["run", "walk", "walk"], ["run", "walk", "walk"])  # the run-cadence rule
    assert P.veto_can_change_step_modes(still, ["side_right", "walk", "walk"], ["side_right", "walk", "walk"])  # side check
    assert not P.veto_can_change_step_modes(np.zeros(3, bool), ["run"] * 3, ["walk"] * 3)


@pytest.mark.parametrize("mode", ["walk", P.RUN_MODE])
def test_step_modes_are_the_full_vetos_and_its_finder_runs_only_when_they_could_differ(demo, mode):
    rec, _ = ear_walk(2)
    windows = P._windows_for(P.model_view(demo, rec)[0], demo.length_s, demo.overlap)
    X = P.model_inputs(demo, rec, windows)

    def table(**kw):
        out = pd.DataFrame({"mode": np.full(len(windows), mode), "mode_raw": np.full(len(windows), mode), "in_domain": None})
        out[["t_start_s", "t_end_s"]] = windows[["t_start_s", "t_end_s"]].to_numpy()
        return P.finish_predictions(out, windows, {}, demo, rec, rec, True, X=X, **kw)

    full, lean = table(), table(veto_for_step_modes=True)
    assert full["still_vetoed"].any()  # the full veto keeps windows of this calm walk in their mode
    t_steps = np.linspace(windows["t_start_s"].iloc[0], windows["t_end_s"].iloc[-1], 200)
    np.testing.assert_array_equal(modes_from_windows(lean, t_steps), modes_from_windows(full, t_steps))
    np.testing.assert_array_equal(lean["side_direction_unsure"].to_numpy(), full["side_direction_unsure"].to_numpy())
    if mode == "walk":  # a walk read walk: nothing the veto does reaches a step, its finder is skipped
        assert np.isnan(lean["window_steps"].to_numpy()).all() and not lean["still_vetoed"].any()
    else:  # a run could be moved by the run-cadence rule once vetoed: the finder runs, the table is the full veto's
        pd.testing.assert_frame_equal(lean, full.drop(columns="still_unsure"))  # (no mark: no step reads 'still')


def test_run_pdr_gives_the_full_vetos_trajectory_and_skips_the_finder_where_it_cannot_matter(demo, monkeypatch):
    rec, _ = ear_walk(1)
    assert predict_recording(demo, rec)["still_vetoed"].any()  # the veto fires on this walk
    calls = []
    real = P.veto_steps
    monkeypatch.setattr(P, "veto_steps", lambda r: calls.append(1) or real(r))
    can_change = P.veto_can_change_step_modes
    lean = run_pdr(rec, model=demo, modes="model")
    n_lean = len(calls)
    monkeypatch.setattr(P, "veto_can_change_step_modes", lambda still, modes, raw: True)  # the finder whenever still
    full = run_pdr(rec, model=demo, modes="model")
    pd.testing.assert_frame_equal(lean.trajectory, full.trajectory)
    pd.testing.assert_frame_equal(lean.steps, full.steps)
    assert len(calls) == n_lean + 1  # the full veto ran its finder once
    gate = predict_recording(demo, rec, still_step_veto=0)  # the statistic's still windows and the model's answers
    corrected = adjacent_window_correction(gate["mode_raw"].to_numpy().astype(str))
    assert n_lean == int(can_change(gate["still"].to_numpy(), corrected, gate["mode_raw"].to_numpy()))


def test_the_pdr_does_not_compute_the_still_unsure_mark_whole_or_chunked(demo, monkeypatch, tmp_path):
    """The mark qualifies a window's ``still`` reading, which no step takes (a step in a still window takes the model's
    raw answer): ``gaitml pdr --model`` never computes its stride rhythm, and its trajectory is the one it gives with
    the mark computed."""
    from gaitml.chunked_run import long_pdr
    from tests.models.test_still_veto_swing import ear_walks_file

    rec, _ = ear_walk(1)
    assert predict_recording(demo, rec)["still_unsure"].any()  # predict marks windows of this walk
    before = run_pdr(rec, model=demo, modes="model")

    def refuse(*a, **k):
        raise AssertionError("the PDR computed the still_unsure mark")

    monkeypatch.setattr(P, "stride_rhythm", refuse)
    whole = run_pdr(rec, model=demo, modes="model")
    pd.testing.assert_frame_equal(whole.trajectory, before.trajectory)
    assert "still_unsure" not in predict_recording(demo, rec, mark_still_unsure=False)
    for rate in (50.0, 20.0):  # the model's own rate, and a file resampled chunk by chunk (the gate after the chunks)
        path = ear_walks_file(tmp_path, rate)
        res = long_pdr(path, model=demo, modes="model", chunk_s=40.0, progress=False)
        assert len(res.trajectory) > 0
