"""The still gate's two rules: |acc| standard deviation (default) and |acc| max - min (the earlier gate)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.models import load_model, predict_recording
from gaitml.models._predict import (
    STILL_RANGE_MS2,
    STILL_RULE,
    STILL_STD_MS2,
    STILL_STEP_VETO_DEFAULT,
    STILL_THRESHOLDS_MS2,
    describe_still_gate,
    still_statistic,
    still_windows,
)
from gaitml.recording import Recording
from tests.conftest import ROOT

G = 9.80665
FS = 50.0


def _rec(mag_extra: np.ndarray, seed: int = 0) -> Recording:
    """A phone whose |acc| is gravity plus ``mag_extra`` (along z), a little sensor noise, a quiet gyroscope."""
    rng = np.random.default_rng(seed)
    n = len(mag_extra)
    acc = np.column_stack([np.zeros(n), np.zeros(n), G + mag_extra]) + rng.normal(0, 0.02, (n, 3))
    return Recording(acc=acc, gyr=rng.normal(0, 0.002, (n, 3)), sampling_rate_hz=FS)


def _windows(n: int, length: int = 75, hop: int = 37) -> pd.DataFrame:
    starts = np.arange(0, n - length + 1, hop)
    return pd.DataFrame({"start": starts, "end": starts + length})


def test_statistics_are_the_std_and_range_of_the_magnitude_in_each_window():
    rng = np.random.default_rng(1)
    rec = _rec(rng.normal(0, 0.5, 600))
    mag = np.linalg.norm(rec.acc, axis=1)
    w = _windows(600)
    want_std = [np.std(mag[a:b]) for a, b in zip(w["start"], w["end"], strict=True)]
    want_rng = [np.ptp(mag[a:b]) for a, b in zip(w["start"], w["end"], strict=True)]
    np.testing.assert_allclose(still_statistic(rec, w, "std"), want_std, rtol=1e-9)
    np.testing.assert_allclose(still_statistic(rec, w, "range"), want_rng, rtol=1e-9)
    # windows of unequal length take the per-window path and agree with it
    w2 = pd.DataFrame({"start": [0, 100, 300], "end": [75, 160, 390]})
    np.testing.assert_allclose(still_statistic(rec, w2, "std"), [np.std(mag[a:b]) for a, b in zip(w2["start"], w2["end"], strict=True)])
    assert STILL_RULE == "std_lp"  # the default; "std" and "range" stay selectable
    with pytest.raises(InputError, match="still rule"):
        still_windows(rec, w, "peak")


def test_a_slow_walkers_bounce_is_gait_and_a_standing_jolt_is_not():
    t = np.arange(1500) / FS
    # a slow hand-held walker: |acc| bounces 0.7 m/s^2 each way at 1.6 steps/s (max - min 1.4 < 2 m/s^2)
    walker = _rec(0.7 * np.sin(2 * np.pi * 1.6 * t))
    # a standing walker's phone: tremor, and one 3 m/s^2 jolt of one sample (20 ms) every 3 s (a tap, a shuffle)
    jolts = np.zeros(len(t))
    jolts[20::150] = 3.0
    standing = _rec(0.05 * np.sin(2 * np.pi * 0.7 * t) + jolts, seed=2)
    w = _windows(len(t))
    assert not still_windows(walker, w).any()  # std 0.49 > 0.41
    assert still_windows(walker, w, "range").all()  # the earlier gate reads the walker as still
    assert still_windows(standing, w).all()  # std about 0.35 with one jolt in a window, under 0.41
    jolted = (still_statistic(standing, w, "range") >= STILL_RANGE_MS2).mean()
    assert jolted > 0.3 and (~still_windows(standing, w, "range")).mean() == jolted  # the earlier gate reads the jolts as gait


def test_predict_takes_the_rule_and_threshold():
    model = load_model(ROOT / "models" / "demo")
    t = np.arange(1500) / FS
    rec = _rec(0.35 * np.sqrt(2) * np.sin(2 * np.pi * 1.6 * t))  # std 0.35 (under 0.41), max - min 0.99 (under 2)
    default = predict_recording(model, rec, still_step_veto=0)  # the gate alone (the step veto off)
    assert default["still"].all() and (default["mode"] == "still").all()
    # with the step veto (the default) the detector finds the bounce's steps: a calm walker, not still
    vetoed = predict_recording(model, rec)
    assert (vetoed["still_vetoed"] | ~default["still"]).mean() > 0.9 and vetoed["still"].mean() < 0.1
    off = predict_recording(model, rec, still_threshold_ms2=0.0)
    assert not off["still"].any() and (off["mode"] != "still").all()
    lower = predict_recording(model, rec, still_threshold_ms2=0.3)
    assert not lower["still"].any()
    old = predict_recording(model, rec, still_rule="range", still_step_veto=0)
    assert old["still"].all()
    pd.testing.assert_series_equal(default["mode_raw"], off["mode_raw"])
    assert STILL_STD_MS2 < STILL_RANGE_MS2 / np.sqrt(8)  # the std gate passes a sinusoidal bounce the range gate reads still


def test_the_gate_in_words_names_the_rule_and_threshold():
    assert describe_still_gate("std", step_veto=0) == f"the standard deviation of |acc| is under {STILL_STD_MS2:g} m/s^2"
    assert (
        describe_still_gate(step_veto=0)
        == f"the standard deviation of |acc| (low-passed at 9 Hz) is under {STILL_THRESHOLDS_MS2['std_lp']:g} m/s^2"
    )
    assert describe_still_gate("range", step_veto=0) == "|acc| swings by under 2 m/s^2"
    # the default names the step veto in force
    assert describe_still_gate() == describe_still_gate(step_veto=0) + (
        "" if STILL_STEP_VETO_DEFAULT is None else f" and fewer than {STILL_STEP_VETO_DEFAULT} steps are detected in it"
    )
    with pytest.raises(InputError, match="still rule"):
        describe_still_gate("peak")


def test_the_predict_warning_states_the_gate_in_force():
    from gaitml.commands.predict import still_warning
    from gaitml.models._predict import describe_still_gate

    line = still_warning(3, 10, "windows")
    assert describe_still_gate() in line and line.startswith("3 of 10 windows")


@pytest.mark.parametrize("bad", [float("nan"), -0.1, "a lot", float("inf")])
def test_a_threshold_that_is_no_finite_number_at_least_zero_is_refused(bad):
    rec = _rec(np.zeros(200))
    with pytest.raises(InputError, match="finite number >= 0"):
        still_windows(rec, _windows(200), threshold_ms2=bad)


def test_the_portable_export_states_the_gate_under_a_new_format_version():
    """A version-1 reader knew only range_ms2 (max - min); the std gate is version 2's."""
    from gaitml.models._export import PORTABLE_FORMAT_VERSION, input_spec

    spec = input_spec(load_model(ROOT / "models" / "demo"))
    still = spec["postprocess"]["still"]
    assert spec["format_version"] == PORTABLE_FORMAT_VERSION >= 2
    assert (still["statistic"], still["threshold_ms2"]) == (STILL_RULE, STILL_THRESHOLDS_MS2[STILL_RULE])
    assert still["range_ms2"] is None if STILL_RULE != "range" else still["range_ms2"] == STILL_RANGE_MS2


def test_the_std_lp_gate_and_the_run_cadence_rule_are_exported_under_version_4():
    """A version 2 or 3 reader knew neither the low-passed statistic nor the run-cadence rule
    (which predict applies by default): an export carrying them must be a version it refuses."""
    from gaitml.models._export import input_spec

    spec = input_spec(load_model(ROOT / "models" / "demo"))
    post = spec["postprocess"]
    assert "run_cadence" in post and post["run_cadence"]["in_force"]
    assert spec["format_version"] >= 4
    if post["still"]["statistic"] == "std_lp":
        assert post["still"]["lowpass_hz"] > 0


def test_predict_json_says_which_gate_ran(tmp_path, capsys):
    import json

    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv

    t = np.arange(1500) / FS
    path = tmp_path / "standing.csv"
    # a standing hand: tremor, no step
    write_gaitml_csv(_rec(0.05 * np.sin(2 * np.pi * 0.7 * t)), path)
    assert main(["predict", str(ROOT / "models" / "demo"), str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["still_gate"] == {
        "statistic": STILL_RULE,
        "threshold_ms2": STILL_THRESHOLDS_MS2[STILL_RULE],
        "step_veto_min_steps": STILL_STEP_VETO_DEFAULT,
    }
    assert out["still_fraction"] == 1.0 and out["still_vetoed_count"] == 0
