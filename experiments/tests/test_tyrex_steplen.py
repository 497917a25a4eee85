"""The step-length study's success check (fixed before measuring) on hand-built tables: it can pass and fail."""

from __future__ import annotations

import pandas as pd

from experiments.scripts.tyrex_steplen import SUCCESS_MOTIONS, success


def _table(ratio_model: float, ratio_fwd: float, err_model: float, err_fwd: float) -> pd.DataFrame:
    rows = []
    for motion in SUCCESS_MOTIONS:
        for variant, ratio, err in (("model/cal", ratio_model, err_model), ("fwd/cal", ratio_fwd, err_fwd)):
            rows.append(
                {
                    "variant": variant,
                    "motion": motion,
                    "disturbance": "NoDist",
                    "held_out": True,
                    "distance_ratio": ratio,
                    "error_10s_pct": err,
                    "drift_deg_per_min": 10.0,
                }
            )
    return pd.DataFrame(rows)


def test_success_passes_and_fails_on_the_criteria():
    ok = success(_table(1.02, 0.95, 15.0, 18.0))
    assert all("NOT MET" not in line for line in ok) and len(ok) == 3
    bad = success(_table(1.15, 0.85, 20.0, 18.0))
    assert all("NOT MET" in line for line in bad)
    assert "Texting 1.15" in bad[0] and "Texting 0.85" in bad[1]
