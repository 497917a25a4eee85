"""The still gate reads a walk recorded at 20 Hz as it reads the same walk at 50 Hz (rule ``std_lp``)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.features import make_windows
from gaitml.models import load_model, predict_recording, resample_recording
from gaitml.models._predict import (
    STILL_LOWPASS_HZ,
    STILL_RULE,
    STILL_RULES,
    STILL_STD_LP_MS2,
    STILL_STEP_VETO_DEFAULT,
    still_statistic,
    still_windows,
)
from gaitml.recording import Recording
from gaitml.simulate import simulate_dataset
from tests.conftest import ROOT

G = 9.80665
#: A window's statistic at 20 Hz may differ from the same window's at 50 Hz by this share, in the median
#: over the windows of a walk (the 20 Hz recording keeps nothing above 10 Hz and its own sample grid).
MEDIAN_MARGIN = 0.05
#: ... and by this share in 90 % of the windows.
P90_MARGIN = 0.12


def _walks():
    """Simulated walkers, one recording per carrying position (hand, swinging hand, pockets), 50 Hz."""
    return simulate_dataset(
        n_subjects=1,
        duration_s=40.0,
        modes=("walk",),
        sampling_rate_hz=50.0,
        seed=11,
        pose="mixed",
        positions=("hand-flat", "swinging-hand", "front-pocket", "back-pocket"),
    )


def _as_gate_reads(rec50: Recording, rate: float, rule: str) -> tuple[np.ndarray, np.ndarray]:
    """The gate's statistic of every 1.5 s window of ``rec50`` and of the same walk recorded at ``rate``, both as predict reads them."""
    w = make_windows(rec50, 1.5, 0.5, min_label_fraction=0.0)
    made = resample_recording(rec50, rate)  # a phone recording at ``rate`` (anti-alias low-pass at 0.45 x rate)
    view = resample_recording(made, 50.0)  # what the model reads: back at its 50 Hz
    n = min(len(w), len(make_windows(view, 1.5, 0.5, min_label_fraction=0.0)))
    w = w.iloc[:n]
    return still_statistic(rec50, w, rule, recorded=rec50), still_statistic(view, w, rule, recorded=made)


def test_the_default_rule_is_the_lowpassed_std():
    assert STILL_RULE == "std_lp" and STILL_RULE in STILL_RULES
    assert {"std", "range"} <= set(STILL_RULES)  # the earlier gates stay one parameter away
    assert 0 < STILL_LOWPASS_HZ < 10.0  # below a 20 Hz phone's Nyquist frequency


@pytest.mark.parametrize("i", range(4))
def test_a_walk_at_20_hz_reads_as_at_50_hz(i):
    rec = _walks()[i]
    s50, s20 = _as_gate_reads(rec, 20.0, STILL_RULE)
    moving = s50 > 0.2  # windows with gait in them (the simulated walkers walk throughout)
    assert moving.mean() > 0.8
    ratio = s20[moving] / s50[moving]
    assert abs(np.median(ratio) - 1.0) <= MEDIAN_MARGIN, (rec.meta.get("position"), np.median(ratio))
    assert np.quantile(np.abs(ratio - 1.0), 0.9) <= P90_MARGIN, (rec.meta.get("position"), np.quantile(np.abs(ratio - 1.0), 0.9))


def test_the_unfiltered_std_reads_a_20_hz_walk_lower():
    """What the rule fixes: the ``std`` statistic of the same walks at 20 Hz falls by more than the margin."""
    ratios = []
    for rec in _walks():
        s50, s20 = _as_gate_reads(rec, 20.0, "std")
        moving = s50 > 0.2
        ratios.append(np.median(s20[moving] / s50[moving]))
    assert min(ratios) < 1.0 - MEDIAN_MARGIN


def test_a_still_phone_stays_still_at_50_and_20_hz():
    model = load_model(ROOT / "models" / "demo")
    rng = np.random.default_rng(5)
    n = 3000
    t = np.arange(n) / 50.0
    table = np.column_stack([np.zeros(n), np.zeros(n), np.full(n, G)]) + rng.normal(0, 0.02, (n, 3))
    # a standing person's hand: slow sway (0.1 m/s^2 at 0.3 Hz) and 8-12 Hz tremor, with sensor noise
    hand = np.column_stack([0.1 * np.sin(2 * np.pi * 0.3 * t), np.zeros(n), G + 0.05 * np.sin(2 * np.pi * 10.0 * t)])
    hand += rng.normal(0, 0.03, (n, 3)) + np.array([0.0, 3.0, 0.0])
    for acc in (table, hand):
        rec = Recording(acc=acc, gyr=rng.normal(0, 0.002, (n, 3)), sampling_rate_hz=50.0)
        for rate in (50.0, 20.0):
            p = predict_recording(model, resample_recording(rec, rate))
            assert p["still"].all() and (p["mode"] == "still").all(), rate


def test_the_rule_is_selectable():
    model = load_model(ROOT / "models" / "demo")
    t = np.arange(1500) / 50.0
    rng = np.random.default_rng(2)
    # a bounce whose power lies above the low-pass: 12 Hz at 0.8 m/s^2 (std about 0.57 unfiltered, about 0.1 low-passed)
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), G + 0.8 * np.sin(2 * np.pi * 12.0 * t)]) + rng.normal(0, 0.02, (len(t), 3))
    rec = Recording(acc=acc, gyr=rng.normal(0, 0.002, (len(t), 3)), sampling_rate_hz=50.0)
    lp = predict_recording(model, rec)
    old = predict_recording(model, rec, still_rule="std")
    assert lp.attrs["still_gate"] == {
        "statistic": "std_lp",
        "threshold_ms2": STILL_STD_LP_MS2,
        "step_veto_min_steps": STILL_STEP_VETO_DEFAULT,
    }
    assert old.attrs["still_gate"]["statistic"] == "std"
    assert lp["still"].all() and not old["still"].any()
    w = make_windows(rec, 1.5, 0.5, min_label_fraction=0.0)
    assert (still_windows(rec, w, "std_lp") == lp["still"].to_numpy()).all()
    with pytest.raises(InputError, match="still rule"):
        predict_recording(model, rec, still_rule="lowpass")


def test_windows_of_unequal_length_agree_with_the_equal_length_path():
    rng = np.random.default_rng(4)
    rec = Recording(acc=rng.normal(0, 0.5, (600, 3)) + np.array([0, 0, G]), sampling_rate_hz=50.0)
    import pandas as pd

    w = pd.DataFrame({"start": [0, 100, 300], "end": [75, 175, 375]})
    same = still_statistic(rec, w, "std_lp")
    each = [still_statistic(rec, w.iloc[[k]], "std_lp")[0] for k in range(3)]
    w2 = pd.DataFrame({"start": [0, 100, 300], "end": [75, 175, 376]})  # one longer window: the per-window path
    np.testing.assert_allclose(same, each, rtol=1e-9)
    np.testing.assert_allclose(still_statistic(rec, w2, "std_lp")[:2], same[:2], rtol=1e-9)


def test_a_long_20_hz_file_read_in_chunks_gets_the_whole_files_gate(tmp_path):
    """The chunked run reads the gate from the file at its own rate too, so its windows match a whole-file prediction."""
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    model = load_model(ROOT / "models" / "demo")
    rec = simulate_dataset(1, 120.0, sampling_rate_hz=50.0, seed=3, pose="mixed", positions=("hand-flat",), pauses=True)[0]
    write_gaitml_csv(resample_recording(rec, 20.0), tmp_path / "r.csv")
    whole = predict_recording(model, read_recording(tmp_path / "r.csv"))
    chunked = long_predict(model, tmp_path / "r.csv", chunk_s=30.0, progress=False)
    assert len(whole) == len(chunked) and whole["still"].any() and not whole["still"].all()
    np.testing.assert_array_equal(chunked["still"].to_numpy(bool), whole["still"].to_numpy(bool))
    np.testing.assert_array_equal(chunked["mode"].to_numpy(str), whole["mode"].to_numpy(str))
