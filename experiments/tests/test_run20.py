"""The lab candidates and the adoption rule of the 20 Hz running-pocket study (experiments/scripts/run20.py)."""

from __future__ import annotations

import types

import numpy as np
import pandas as pd
import pytest

from experiments.scripts import run20
from gaitml.recording import Recording

FS = 50.0


def _steps(peaks, cadences):
    return pd.DataFrame({"start": peaks, "peak": peaks, "end": peaks, "cadence_hz": cadences})


def _rec(n=500):
    return Recording(acc=np.tile([0.0, 0.0, 9.81], (n, 1)), sampling_rate_hz=FS, meta={"id": "x"}, check_units=False)


def test_lowest_window_cadence_takes_the_slowest_step_near_the_window_and_nan_without_one():
    rec = _rec()
    w = pd.DataFrame({"start": [0, 100, 300], "end": [75, 175, 375]})
    # steps at 50 (2.5/s), 110 (3.0/s), 180 (1.9/s: 5 samples after the second window, within the 0.5 s reach)
    cad = run20.lowest_window_cadence(rec, w, _steps([50, 110, 180], [2.5, 3.0, 1.9]), reach_s=0.5)
    assert cad[0] == pytest.approx(2.5)  # the step at 110 lies 35 samples past the end, beyond the 25-sample reach
    assert cad[1] == pytest.approx(1.9)  # the slowest of 110 and 180
    assert np.isnan(cad[2])  # no step within reach
    assert np.isnan(run20.lowest_window_cadence(rec, w, _steps([], []), reach_s=0.5)).all()


def _table(modes, in_domain):
    n = len(modes)
    return pd.DataFrame(
        {
            "start": np.arange(n) * 37,
            "end": np.arange(n) * 37 + 75,
            "mode": modes,
            "in_domain": np.array(in_domain, dtype=object),
            "out_of_domain_reason": np.array(["" if v else "unlike the training data" for v in in_domain], dtype=object),
        }
    )


def test_walk_cadence_candidate_flags_only_in_domain_walk_windows_at_a_running_cadence(monkeypatch):
    import gaitml.models._predict as pr

    rec = _rec()
    p = _table(["walk", "walk", "run", "walk", "walk"], [True, True, True, False, True])
    # steps: fast (2.8/s) under windows 0-3, a walking cadence (1.8/s) near window 4
    peaks = [10, 40, 80, 120, 150, 190, 225]
    cads = [2.8, 2.8, 2.8, 2.8, 2.8, 1.8, 1.8]
    monkeypatch.setattr(pr, "recording_steps", lambda r: _steps(peaks, cads))
    model = types.SimpleNamespace(sampling_rate_hz=FS)
    q = run20.apply_candidate(p, model, rec, "walk-cadence")
    assert q["candidate_flag"].tolist() == [True, True, False, False, False]
    assert list(q["in_domain"]) == [False, False, True, False, True]
    assert q["out_of_domain_reason"].iloc[0] == run20.CANDIDATE_REASON["walk-cadence"]
    assert q["out_of_domain_reason"].iloc[3] == "unlike the training data"  # an earlier reason is kept
    assert list(p["in_domain"]) == [True, True, True, False, True]  # the input table is not changed
    assert run20.apply_candidate(p, model, rec, None) is p
    with pytest.raises(ValueError, match="unknown candidate"):
        run20.apply_candidate(p, model, rec, "nope")


CSV_COLS = ["subject", "phone", "motion", "n", "right", "flagged", "wrong", "left_out", "score_rate_hz"]


def _run(stem, rp20, phoning_native, sim_walk):
    """A pair of tyrex_modes outputs: RunningPocket at 20 Hz (right, flagged, wrong), Phoning as recorded, a simulator row's right."""
    rows = []
    for person in ("A", "B", "C"):
        rows.append([person, "p", "Phoning", 100, *phoning_native, person, np.nan])
        rows.append([person, "p", "RunningPocket", 100, 90, 5, 5, person, np.nan])
        rows.append([person, "p", "Phoning", 100, 95, 0, 5, person, 20.0])
        rows.append([person, "p", "RunningPocket", 100, *rp20, person, 20.0])
    pd.DataFrame(rows, columns=CSV_COLS).to_csv(stem.with_suffix(".csv"), index=False)
    sim = "| position | mode | n | right | flagged | silently wrong | right over folds |\n|---|---|---|---|---|---|---|\n"
    unt = "| what | windows | flagged |\n|---|---|---|\n| simulator bag (held-out seed) | 10 | 0.80/0.80/0.70 |\n"
    txt = (
        "held-out simulator (seed 2024, 2 subjects)\n\n" + sim + f"| front-pocket | walk | 100 | {sim_walk} | 0.00 | 0.10 | 0.88-0.90 |\n"
        "\nnot trained on, flagged (one figure per fold)\n\n"
        + unt
        + "\nheld-out simulator recorded at 20 Hz (seed 2024)\n\n"
        + sim
        + "| front-pocket | walk | 100 | 0.90 | 0.00 | 0.10 | 0.88-0.92 |\n"
        "\nnot trained on, recorded at 20 Hz, flagged (one figure per fold)\n\n" + unt
    )
    stem.with_suffix(".md").write_text(txt)
    return stem


def test_the_adoption_rule_passes_a_flag_of_the_wrong_windows_and_fails_native_costs(tmp_path):
    base = _run(tmp_path / "base", (80, 5, 15), (95, 0, 5), "0.89")
    good = _run(tmp_path / "good", (80, 18, 2), (95, 0, 5), "0.89")
    fails, lines = run20.adoption(base, good)
    assert fails == [] and any(line.startswith("| RunningPocket | 20 Hz |") for line in lines)
    costly = _run(tmp_path / "costly", (80, 18, 2), (93, 2, 5), "0.89")  # native Phoning right 0.95 -> 0.93
    assert any("Phoning as recorded: 3" in f for f in run20.adoption(base, costly)[0])
    nothing = _run(tmp_path / "nothing", (80, 5, 15), (95, 0, 5), "0.89")  # RunningPocket at 20 Hz unchanged
    assert any("RunningPocket 20 Hz: 2" in f for f in run20.adoption(base, nothing)[0])
    sim_falls = _run(tmp_path / "sim", (80, 18, 2), (95, 0, 5), "0.85")  # below 0.89 - spread 0.02
    assert any(f.startswith("simulator") and "front-pocket walk" in f for f in run20.adoption(base, sim_falls)[0])


def test_window_rows_count_the_steps_of_every_moving_window():
    """The diagnosis' "steps in window" row takes the median of ``window_steps`` over moving windows; predict's column
    holds the veto's counts only where the still gate reads a window still (NaN elsewhere), so run20 counts the default
    detector's steps in every window itself (the steps whose cadence the row above reads)."""
    from gaitml.models import load_model
    from gaitml.simulate import simulate_dataset
    from tests.conftest import ROOT

    rec = simulate_dataset(n_subjects=1, duration_s=40.0, modes=("walk",), seed=3)[0]
    rows = run20.window_rows(load_model(ROOT / "models" / "demo"), rec, "walk")
    assert len(rows) > 10 and not rows["still"].any()
    k = rows["window_steps"].to_numpy(float)
    assert np.isfinite(k).all() and np.median(k) >= 2  # 1.5 s of walking holds two steps or more
