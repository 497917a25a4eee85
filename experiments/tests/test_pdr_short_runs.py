"""The short-run study's lab scripts (pdr_short_runs_sim, tyrex_pdr_nonforward) on hand-built tables: P3 can pass and fail."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.pdr_short_runs_sim import VARIANTS, summarise, verdicts
from experiments.scripts.tyrex_pdr_nonforward import forced

OFF, ON = VARIANTS[0][0], VARIANTS[1][0]


def _long(acc_on_shift: float, err_on_shift: float, route: str = "arc") -> pd.DataFrame:
    rows = []
    for seed in range(10):
        acc, err = 0.95 + 0.01 * (seed % 3), 2.0 + 0.5 * (seed % 4)
        rows.append({"route": route, "seed": seed, "variant": OFF, "mode_accuracy": acc, "end_error_pct": err, "short_run_steps": 0})
        rows.append(
            {
                "route": route,
                "seed": seed,
                "variant": ON,
                "mode_accuracy": acc + acc_on_shift,
                "end_error_pct": err + err_on_shift,
                "short_run_steps": 2,
            }
        )
    return pd.DataFrame(rows)


def test_p3_passes_within_the_seed_spread_and_fails_beyond_it():
    same = summarise(_long(0.0, 0.0))
    assert same.loc[("arc", "change (on - off)"), "mode_accuracy mean"] == 0.0
    assert same.loc[("arc", ON), "steps moved (sum)"] == 20
    assert all(" ok" in line and "WORSE" not in line for line in verdicts(same, None))
    se = same.loc[("arc", OFF), "mode_accuracy se"]
    assert "WORSE" not in verdicts(summarise(_long(-0.5 * se, 0.0)), None)[0]
    assert "WORSE" in verdicts(summarise(_long(-2.0 * se, 0.0)), None)[0]
    assert "WORSE" in verdicts(summarise(_long(0.0, 5.0)), None)[0]


def test_p3a_reads_the_demo_route_against_the_rectangle_spread():
    summary = summarise(_long(0.0, 0.0, route="rectangle"))
    sd = summary.loc[("rectangle", OFF), "end_error_pct sd"]
    demo = pd.DataFrame({"variant": [OFF, ON], "end_error_pct": [1.97, 1.97 + 0.5 * sd]})
    assert "ok" in verdicts(summary, demo)[-1]
    demo = pd.DataFrame({"variant": [OFF, ON], "end_error_pct": [1.97, 1.97 + 2.0 * sd]})
    assert "WORSE" in verdicts(summary, demo)[-1]


def test_forced_replaces_only_the_modes_of_a_copy():
    prep = {"runs": {"model": {"modes": np.array(["walk", "backward"]), "theta": np.zeros(2)}}}
    out = forced(prep, ["walk", "walk"])
    assert out["runs"]["cf"]["modes"].tolist() == ["walk", "walk"]
    assert out["runs"]["cf"]["theta"] is prep["runs"]["model"]["theta"]
    assert prep["runs"]["model"]["modes"].tolist() == ["walk", "backward"] and "cf" not in prep["runs"]
