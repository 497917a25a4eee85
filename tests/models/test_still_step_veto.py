"""The still gate's step veto: a window in which the default step detector finds steps is not still.

A calm walker with the phone at the ear varies |acc| as little as a standing hand (the ``std_lp`` statistic under
its threshold), but its steps repeat and ``adaptive`` finds them: with the veto (on by default,
``STILL_STEP_VETO_MIN_STEPS``) such windows keep the model's mode, while a phone lying still or a standing hand stays
``still``; the whole-file and chunked runs agree; on the real tyrex Phoning walks the veto answers fewer moving
windows ``still`` and keeps the standing ones still.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import gaitml.models._predict as P
from gaitml.errors import InputError
from gaitml.models import load_model, predict_recording, resample_recording
from gaitml.models._predict import (
    STILL_STEP_VETO_DEFAULT,
    STILL_STEP_VETO_MIN_STEPS,
    recording_steps,
    still_step_veto_threshold,
    window_step_counts,
)
from gaitml.recording import Recording
from tests.conftest import ROOT, shared

G = 9.80665
FS = 50.0


def calm_walker(seconds: float = 60.0, step_hz: float = 1.7, amp: float = 0.4, stand_s: float = 0.0, seed: int = 0) -> Recording:
    """A phone at the ear of a calm walker: |acc| bounces ``amp`` m/s^2 at the step rate (its second harmonic and a
    weaker left / right stride term beside it), standing ``stand_s`` s before and after; std_lp about 0.3 m/s^2,
    under the gate's 0.38."""
    rng = np.random.default_rng(seed)
    t = np.arange(int((seconds + 2 * stand_s) * FS)) / FS
    walk = (t >= stand_s) & (t < stand_s + seconds)
    bounce = amp * (np.sin(2 * np.pi * step_hz * t) + 0.3 * np.sin(4 * np.pi * step_hz * t + 0.5) + 0.1 * np.sin(np.pi * step_hz * t))
    mag = G + np.where(walk, bounce, 0.03 * np.sin(2 * np.pi * 0.4 * t))
    acc = np.column_stack([np.full_like(t, 0.1), np.full_like(t, 0.2), mag]) + rng.normal(0, 0.03, (len(t), 3))
    sway = np.column_stack([0.05 * np.sin(np.pi * step_hz * t), 0.03 * np.sin(2 * np.pi * step_hz * t), np.zeros_like(t)])
    gyr = sway * walk[:, None] + rng.normal(0, 0.005, (len(t), 3))
    return Recording(acc=acc, gyr=gyr, sampling_rate_hz=FS)


def still_phone(seconds: float = 60.0, seed: int = 1) -> Recording:
    """A phone lying on a table (sensor noise only)."""
    rng = np.random.default_rng(seed)
    n = int(seconds * FS)
    acc = np.column_stack([np.zeros(n), np.zeros(n), np.full(n, G)]) + rng.normal(0, 0.02, (n, 3))
    return Recording(acc=acc, gyr=rng.normal(0, 0.002, (n, 3)), sampling_rate_hz=FS)


@pytest.fixture(scope="module")
def demo():
    return load_model(ROOT / "models" / "demo")


def test_the_named_defaults_and_their_checks():
    assert STILL_STEP_VETO_MIN_STEPS == 2 and STILL_STEP_VETO_DEFAULT == STILL_STEP_VETO_MIN_STEPS
    assert still_step_veto_threshold(None) == STILL_STEP_VETO_DEFAULT
    assert still_step_veto_threshold(0) is None and still_step_veto_threshold(3) == 3 and still_step_veto_threshold(2.0) == 2
    for bad in (-1, 1.5, "two", float("nan"), True):
        with pytest.raises(InputError, match="whole number of steps"):
            still_step_veto_threshold(bad)


def test_the_default_follows_the_named_default(demo, monkeypatch):
    rec = calm_walker(30.0)
    on = predict_recording(demo, rec)
    assert on.attrs["still_gate"]["step_veto_min_steps"] == STILL_STEP_VETO_DEFAULT and on["still_vetoed"].any()
    monkeypatch.setattr(P, "STILL_STEP_VETO_DEFAULT", None)  # one constant turns it off in every path
    off = predict_recording(demo, rec)
    assert off.attrs["still_gate"]["step_veto_min_steps"] is None and not off["still_vetoed"].any() and off["still"].all()


def test_step_counts_are_the_peaks_inside_each_window():
    steps = pd.DataFrame({"peak": [10, 50, 74, 75, 200]})
    w = pd.DataFrame({"start": [0, 75, 100], "end": [75, 150, 175]})
    np.testing.assert_array_equal(window_step_counts(w, steps), [3, 1, 0])
    np.testing.assert_array_equal(window_step_counts(w, steps.iloc[:0]), [0, 0, 0])


def test_a_calm_walker_whose_acc_varies_little_is_not_still(demo):
    rec = calm_walker()
    gate_only = predict_recording(demo, rec, still_step_veto=0)
    assert gate_only["still"].mean() > 0.9  # the |acc| statistic alone reads the calm walk still
    table = predict_recording(demo, rec)
    assert table["still"].mean() < 0.05 and (table["mode"] != "still").mean() > 0.95
    vetoed = table["still_vetoed"].to_numpy(bool)
    assert vetoed.mean() > 0.9 and (table["window_steps"].to_numpy()[vetoed] >= STILL_STEP_VETO_MIN_STEPS).all()
    # the model's answer is what the vetoed windows report (the adjacent-window correction's, as without the gate)
    off = predict_recording(demo, rec, still_threshold_ms2=0.0)
    np.testing.assert_array_equal(table["mode"].to_numpy()[vetoed], off["mode"].to_numpy()[vetoed])


def test_a_still_phone_and_a_standing_hand_stay_still(demo):
    table = predict_recording(demo, still_phone())
    assert table["still"].all() and not table["still_vetoed"].any() and (table["window_steps"] == 0).all()
    both = predict_recording(demo, calm_walker(40.0, stand_s=30.0))
    t_mid = 0.5 * (both["t_start_s"] + both["t_end_s"]).to_numpy()
    standing = (t_mid < 29.0) | (t_mid > 71.0)
    walking = (t_mid > 31.0) & (t_mid < 69.0)
    assert both["still"].to_numpy()[standing].mean() > 0.95  # no steps there: still as before
    assert both["still"].to_numpy()[walking].mean() < 0.05


def test_the_steps_are_found_once_per_finder(demo, monkeypatch):
    calls = []
    real = P.recording_steps

    def counting(rec, swing_periodicity=0.0):
        calls.append(float(swing_periodicity))
        return real(rec, swing_periodicity)

    monkeypatch.setattr(P, "recording_steps", counting)
    predict_recording(demo, calm_walker(30.0))
    # the veto's steps (the swing stage on: the walker has a gyroscope) once; the run-cadence rule's, at adaptive's
    # defaults, at most once (when some window reads run)
    assert calls.count(P.STILL_STEP_SWING_PERIODICITY) == 1 and calls.count(0.0) <= 1 and len(calls) <= 2
    calls.clear()
    predict_recording(demo, calm_walker(30.0, amp=2.0))  # a vigorous walk: nothing reads still, no steps needed for the gate
    assert calls in ([], [0.0])  # at most the run-cadence rule's, at the defaults
    calls.clear()
    monkeypatch.setattr(P, "STILL_STEP_SWING_PERIODICITY", 0.0)  # the same steps for both rules: found once, shared
    predict_recording(demo, calm_walker(30.0))
    assert calls == [0.0]


def _count_detector_runs(monkeypatch) -> list[float]:
    """Every run of the ``adaptive`` detector from here on, as the swing stage's setting it ran with (0: off)."""
    import gaitml.steps.adaptive as adaptive

    calls: list[float] = []
    real = adaptive.AdaptiveStepDetector.detect

    def counting(self, *a, **k):
        calls.append(float(self.gyro_swing_min_periodicity or 0.0))
        return real(self, *a, **k)

    monkeypatch.setattr(adaptive.AdaptiveStepDetector, "detect", counting)
    return calls


def test_found_steps_are_read_back_for_the_same_recording_and_finder_only(monkeypatch):
    calls = _count_detector_runs(monkeypatch)
    rec, other = calm_walker(30.0), calm_walker(30.0, seed=5)
    found: dict = {}
    first = P.steps_found_once(found, rec, veto=True)
    assert P.steps_found_once(found, rec, veto=True) is first and len(calls) == 1  # read back, not found again
    P.steps_found_once(found, rec, veto=False)  # the run-cadence rule's (no swing stage): a run of its own
    P.steps_found_once(found, other, veto=True)  # another recording: a run of its own, whatever the dict holds
    assert calls == [P.STILL_STEP_SWING_PERIODICITY, 0.0, P.STILL_STEP_SWING_PERIODICITY]
    pd.testing.assert_frame_equal(first, P.veto_steps(rec))  # the table a run of its own gives
    # without a gyroscope the veto's finder is the rule's (the swing stage cannot run): one run serves both
    calls.clear()
    acc_only = rec.replace(gyr=None)
    found = {}
    steps = P.steps_found_once(found, acc_only, veto=True)
    assert P.steps_found_once(found, acc_only, veto=False) is steps and calls == [0.0]
    pd.testing.assert_frame_equal(steps, P.recording_steps(acc_only))


def test_a_resampled_chunk_without_a_gyroscope_finds_its_steps_once(monkeypatch, tmp_path):
    """long_predict of a file at another rate than the model's (the still gate after the chunks): a chunk holding windows
    read run and windows read still needs the run-cadence rule's steps and the veto's, which are the same steps without
    a gyroscope: found once per chunk (they were found twice), the same table as when each pass finds its own."""
    from gaitml.chunked_run import long_predict
    from gaitml.io import write_gaitml_csv
    from gaitml.simulate import simulate_dataset

    acc_model = load_model(ROOT / "models" / "demo-acc")
    rec = simulate_dataset(1, 120.0, modes=["run", "walk"], sampling_rate_hz=100.0, seed=7, pauses=True, pose="mixed")[0]
    path = tmp_path / "no_gyro.csv"
    write_gaitml_csv(rec.replace(gyr=None), path)
    calls = _count_detector_runs(monkeypatch)
    fast = long_predict(acc_model, path, chunk_s=37.0, progress=False)
    n_fast = len(calls)
    assert (fast["mode_raw"] == "run").any() and fast["still"].any()  # both rules need steps
    monkeypatch.setattr(P, "steps_found_once", lambda found, r, veto: P.veto_steps(r) if veto else P.recording_steps(r))
    calls.clear()  # every pass finds its own steps (the code before the sharing)
    plain = long_predict(acc_model, path, chunk_s=37.0, progress=False)
    pd.testing.assert_frame_equal(fast, plain)
    n_chunks = int(np.ceil(120.0 / 37.0))
    assert n_fast <= n_chunks < len(calls)


@pytest.mark.parametrize("rate", [50.0, 20.0])
def test_whole_and_chunked_runs_agree(demo, tmp_path, rate):
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    rec = calm_walker(90.0, stand_s=45.0, seed=3)
    path = tmp_path / "calm.csv"
    write_gaitml_csv(rec if rate == FS else resample_recording(rec, rate), path)
    whole = predict_recording(demo, read_recording(path))
    chunked = long_predict(demo, path, chunk_s=40.0, progress=False)
    assert len(whole) == len(chunked) and whole["still_vetoed"].sum() > 50 and whole["still"].sum() > 50
    # each chunk finds its own steps, on adaptive's cadence grid with a 30 s margin: the whole file's steps here
    for col in ("still", "still_vetoed", "mode"):
        np.testing.assert_array_equal(whole[col].to_numpy(), chunked[col].to_numpy(), err_msg=col)
    assert chunked.attrs["still_gate"]["step_veto_min_steps"] == STILL_STEP_VETO_DEFAULT
    off = long_predict(demo, path, chunk_s=40.0, progress=False, still_step_veto=0)
    assert not off["still_vetoed"].any() and off["still"].sum() > whole["still"].sum() + 50


def test_the_predict_command_reports_the_vetoed_windows(demo, tmp_path, capsys):
    import json

    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv

    path = tmp_path / "calm.csv"
    write_gaitml_csv(calm_walker(40.0, stand_s=20.0), path)
    assert main(["predict", str(ROOT / "models" / "demo"), str(path), "--json"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    n_vetoed = sum(w["still_vetoed"] for w in out["windows"])
    assert out["still_vetoed_count"] == n_vetoed > 30 and out["still_gate"]["step_veto_min_steps"] == STILL_STEP_VETO_DEFAULT
    assert "hold detected steps and keep their mode" in cap.err and "fewer than 2 steps are detected" in cap.err
    # --still-step-veto off: the gate alone, and the line says so
    assert main(["predict", str(ROOT / "models" / "demo"), str(path), "--json", "--still-step-veto", "off"]) == 0
    cap = capsys.readouterr()
    off = json.loads(cap.out)
    assert off["still_vetoed_count"] == 0 and off["still_gate"]["step_veto_min_steps"] is None
    assert off["still_fraction"] > out["still_fraction"] + 0.3 and "steps are detected" not in cap.err
    for bad in ("many", "1.5", "-1"):
        assert main(["predict", str(ROOT / "models" / "demo"), str(path), "--still-step-veto", bad]) != 0
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and ("--still-step-veto" in err[0] or "whole number of steps" in err[0])


def test_the_portable_export_states_the_veto(demo):
    from gaitml.models._export import input_spec

    spec = input_spec(demo)
    assert spec["format_version"] >= 5  # a version 4 reader knew no veto: it must refuse the export
    veto = spec["postprocess"]["still"]["step_veto"]
    assert veto["in_force"] == (STILL_STEP_VETO_DEFAULT is not None) and veto["min_steps"] == STILL_STEP_VETO_MIN_STEPS
    assert "peak lies inside the window" in veto["rule"]


def _tyrex_windows(data, motion: str):
    """Each tyrex recording of ``motion`` with motion capture at 50 Hz, and its windows' truth: moving / standing by the
    body speed (gaitml.evaluation.trajectory.moving_samples, more than half of the window)."""
    from gaitml.evaluation.trajectory import moving_samples
    from gaitml.features import make_windows
    from gaitml.io import read_segments
    from gaitml.io.tyrex import read_tyrex_truth
    from gaitml.pipeline.folder_source import tyrex_manifest

    man = tyrex_manifest(data)
    out = []
    for row in man[(man["truth"] != "") & (man["motion"] == motion)].to_dict("records"):
        truth = read_tyrex_truth(data / row["file"])
        # a recording with a sensor gap comes in segments: the one the capture covers longest
        rec = max(
            read_segments(data / row["file"]),
            key=lambda r: min(r.meta["t0_original_s"] + r.duration_s, truth.t_s[-1]) - max(r.meta["t0_original_s"], truth.t_s[0]),
        )
        r50 = resample_recording(rec, FS)
        m = moving_samples(r50.t_s + r50.meta["t0_original_s"], truth.t_s, truth.pos_m[:, :2])
        w = make_windows(r50, 1.5, 0.5, min_label_fraction=0.0)
        cs_move = np.concatenate([[0], np.cumsum(m == 1)])
        cs_still = np.concatenate([[0], np.cumsum(m == 0)])
        s, e = w["start"].to_numpy(), w["end"].to_numpy()
        out.append((rec, (cs_move[e] - cs_move[s]) > 0.5 * (e - s), (cs_still[e] - cs_still[s]) > 0.5 * (e - s)))
    return out


@pytest.mark.realdata
def test_real_phoning_walks_lose_still_windows_and_standing_stays_still(demo):
    """The tyrex Phoning walks (three people, three phones): with the veto, at most 6 % of the windows in which the
    motion capture shows the body moving are answered ``still`` (measured 118 of 2290, 0.052; 153, 0.067, without),
    and the standing windows read still fall by at most a tenth (measured 400 -> 379 of 550). The gate reads no
    model output, so the shipped model's windows serve (its training on these people does not enter the gate)."""
    items = _tyrex_windows(shared("tyrex-attitude"), "Phoning")
    assert len(items) >= 9
    moving_still = {0: 0, None: 0}
    standing_still = {0: 0, None: 0}
    n_moving = n_standing = 0
    for rec, moving, standing in items:
        for veto in (0, None):
            t = predict_recording(demo, rec, still_step_veto=veto)
            assert len(t) == len(moving)
            still = t["still"].to_numpy(bool)
            moving_still[veto] += int(still[moving].sum())
            standing_still[veto] += int(still[standing].sum())
        n_moving += int(moving.sum())
        n_standing += int(standing.sum())
    assert n_moving > 1500 and n_standing > 300
    assert moving_still[None] / n_moving <= 0.06 and moving_still[None] <= 0.85 * moving_still[0]
    assert standing_still[None] >= 0.9 * standing_still[0] and standing_still[None] / n_standing >= 0.6


def test_a_recording_shorter_than_the_detector_has_no_steps():
    rec = still_phone(1.0)
    steps = recording_steps(rec)
    assert steps.empty and {"peak", "cadence_hz"} <= set(steps.columns)
