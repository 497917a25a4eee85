"""The Swinging distance study's pieces on hand-built inputs: the ratio split, the adoption rule (it can pass and
fail) and the per-step candidate inputs against known signals."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.tyrex_steplen import WALK_MOTIONS
from experiments.scripts.tyrex_swingdist import CANDIDATES, adoption, candidate_features, decompose
from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording


def test_decompose_splits_the_ratio_into_coverage_bias_extra():
    # 5 steps; the first and a step after a pause have no true length
    samples = pd.DataFrame({"true_length_m": [np.nan, 0.5, 0.5, np.nan, 0.5]})
    pred = np.full(5, 0.4)
    d = decompose(samples, pred, true_m=2.0)
    assert d["coverage"] == pytest.approx(1.5 / 2.0)  # 0.5 m of the walk lies in no step pair
    assert d["bias"] == pytest.approx(1.2 / 1.5)  # the line is 20 % short where it can be checked
    assert d["extra"] == pytest.approx(2.0 / 1.2)  # the two steps without truth still add length
    assert d["ratio"] == pytest.approx(d["coverage"] * d["bias"] * d["extra"]) and d["ratio"] == pytest.approx(1.0)


def _table(ratios: dict[str, dict[str, float]], swing_people: dict[str, dict[str, float]]) -> pd.DataFrame:
    """Held-out rows: per motion 9 NoDist recordings (3 per person) with the given candidate ratios; Swinging's per person."""
    rows = []
    for motion in WALK_MOTIONS:
        for person in ("A", "B", "C"):
            for _ in range(3):
                r = {name: (swing_people[name][person] if motion == "Swinging" else ratios[name][motion]) for name in CANDIDATES}
                rows.append(
                    {
                        "held_out": True,
                        "disturbance": "NoDist",
                        "motion": motion,
                        "subject": person,
                        **{f"{k}_ratio": v for k, v in r.items()},
                    }
                )
    return pd.DataFrame(rows)


def test_adoption_rule_passes_and_fails():
    base = {"Texting": 1.05, "Phoning": 1.0, "FrontPocket": 1.0, "BackPocket": 0.88}
    ratios = {
        "eq12": base,
        "f": {**base, "Texting": 1.30},  # Texting out of band and further from 1 than eq12: fails (2)
        "f+range4": base,
        "f+gyro": {**base, "BackPocket": 0.87},  # out of band but within 0.02 of eq12's distance from 1: passes (2)
    }
    swing = {
        "eq12": {"A": 0.97, "B": 1.03, "C": 0.77},
        "f": {"A": 0.97, "B": 1.03, "C": 0.97},
        "f+range4": {"A": 0.97, "B": 0.8, "C": 0.8},  # Swinging median 0.8: fails (1); nearer 1 only for C
        "f+gyro": {"A": 1.05, "B": 1.0, "C": 0.98},
    }
    out = adoption(_table(ratios, swing))
    assert out.loc["adopted", "f+gyro"] == "yes"
    assert out.loc["adopted", "f"] == "no" and out.loc["(2) others in band or within 0.02 of eq12", "f"].startswith("no (Texting")
    assert out.loc["(1) Swinging 0.9-1.1", "f+range4"] == "no" and out.loc["(3) Swinging nearer 1 for >= 2 people", "f+range4"] == "no (1)"
    assert out.loc["adopted", "eq12"] == "no"  # the reference row is never nearer 1 than itself


def test_candidate_features_on_known_signals():
    fs, n = 100.0, 2000
    t = np.arange(n) / fs
    amp_w, amp_a = 2.0, 3.0
    gyr = np.column_stack([amp_w * np.sin(2 * np.pi * 1.0 * t), np.zeros(n), np.zeros(n)])  # a 1 Hz swing, 2 rad/s
    acc = np.column_stack([np.zeros(n), np.zeros(n), GRAVITY_MS2 + amp_a * np.sin(2 * np.pi * 2.0 * t)])
    rec = Recording(acc=acc, gyr=gyr, sampling_rate_hz=fs, meta={"id": "x"}, check_units=False)
    steps = pd.DataFrame({"start": np.arange(500, 1500, 50), "end": np.arange(550, 1550, 50), "period_s": 0.5})
    f = candidate_features(rec, steps)
    assert len(f) == len(steps)
    # a whole number of swing half-cycles per step: the RMS of a sine, amplitude / sqrt(2)
    assert np.allclose(f["gyro_rms_rads"], amp_w / np.sqrt(2), rtol=0.05)
    # |acc| - g swings +-3 m/s^2 (smoothed over 3 samples: a little less): range 6, fourth root ~1.57
    assert np.allclose(f["range4"], (2 * amp_a) ** 0.25, rtol=0.02)
