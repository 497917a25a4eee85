"""The walk-ratio study's step-length rules and its measurement, on hand-made steps (no shared data needed)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.tyrex_walkratio import (
    CANDIDATES,
    WALK_RATIO_M_PER_SPM,
    WALK_RUN_TRANSITION_HZ,
    candidate_lengths,
    capped_cadence,
    measure_table,
)
from gaitml.pdr.step_length import StepLengthModel


def _prep(freq, modes=None):
    n = len(freq)
    feats = pd.DataFrame({"freq_hz": freq, "var_ms2sq": np.ones(n), "a_max_ms2": np.full(n, 6.0), "a_min_ms2": np.full(n, -4.0)})
    return {"t_step": np.arange(n, dtype=float), "features": feats, "modes": np.array(modes or ["walk"] * n)}


def test_the_rules_give_the_literature_lengths():
    f = np.array([1.2, 1.8, 2.8])
    today = candidate_lengths(_prep(f), CANDIDATES["today"])
    plain = candidate_lengths(_prep(f), CANDIDATES["walk ratio"])
    capped = candidate_lengths(_prep(f), CANDIDATES["walk ratio, capped"])
    np.testing.assert_allclose(today, 0.25 + 0.25 * f)
    np.testing.assert_allclose(plain, WALK_RATIO_M_PER_SPM * 60 * f)  # 0.46 m at 1.2 steps/s, 0.69 m at 1.8
    assert 0.45 < plain[0] < 0.47 and 0.68 < plain[1] < 0.70
    np.testing.assert_allclose(capped[:2], plain[:2])  # walking cadences: the cap does not act
    assert capped[2] == pytest.approx(WALK_RATIO_M_PER_SPM * 60 * WALK_RUN_TRANSITION_HZ)  # held at 140 steps/min
    assert capped[2] < plain[2]


def test_run_steps_keep_weinberg():
    p = _prep(np.array([2.8, 2.8]), ["walk", "run"])
    L = candidate_lengths(p, CANDIDATES["walk ratio"])
    assert L[1] == pytest.approx(StepLengthModel().predict(p["features"].iloc[[1]], ["run"])[0])
    assert L[0] != pytest.approx(L[1])


def test_capped_cadence_patch_is_undone_even_on_error():
    original = StepLengthModel.predict
    feats = _prep(np.array([3.0]))["features"]
    with capped_cadence(2.0):
        assert StepLengthModel().predict(feats, ["walk"])[0] == pytest.approx(0.25 + 0.25 * 2.0)
    assert StepLengthModel.predict is original
    with pytest.raises(RuntimeError), capped_cadence(2.0):
        raise RuntimeError("boom")
    assert StepLengthModel.predict is original
    assert StepLengthModel().predict(feats, ["walk"])[0] == pytest.approx(0.25 + 0.25 * 3.0)


def test_measurement_recovers_a_known_walk_ratio():
    """Steps that follow L = 0.005 m/(steps/min) x cadence: the table's walk ratio and speed come out right."""
    rng = np.random.default_rng(0)
    items, preps = [], []
    for subj, f0 in (("A", 1.5), ("B", 1.8)):
        f = f0 + 0.05 * rng.standard_normal(200)
        L = 0.005 * 60 * f
        L[:5] = np.nan  # steps without a true length are left out
        items.append({"subject": subj, "phone": "p", "motion": "Texting", "disturbance": "NoDist"})
        preps.append({"samples": pd.DataFrame({"t_s": np.arange(200.0), "freq_hz": f, "true_length_m": L})})
    steps, table = measure_table(items, preps)
    assert len(steps) == 390
    np.testing.assert_allclose(steps["walk_ratio"], 0.005)
    row = table[(table["subject"] == "B")].iloc[0]
    assert row["cadence_hz"] == pytest.approx(1.8, abs=0.02)
    assert row["true_L_m"] == pytest.approx(0.005 * 60 * row["cadence_hz"], rel=0.02)
    assert row["speed_ms"] == pytest.approx(row["true_L_m"] * row["cadence_hz"], rel=0.05)
    assert row["slope_m_per_hz"] == pytest.approx(0.3, rel=0.05)
    assert set(table["subject"]) == {"A", "B", "all"}
