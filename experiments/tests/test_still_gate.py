"""The still-gate study's own pieces: the threshold criterion and the gated scores, on known answers."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.still_gate import equal_standing_threshold, gated_table


def test_equal_standing_threshold_reads_as_many_standing_windows_still_as_the_range_rule():
    rng = np.random.default_rng(0)
    sd = rng.lognormal(-1.2, 0.6, 2000)
    rg = 3.0 * sd * rng.lognormal(0, 0.3, 2000)  # the range grows with the std, with scatter
    thr = equal_standing_threshold(sd, rg, 2.0)
    assert abs(np.mean(sd < thr) - np.mean(rg < 2.0)) < 0.01
    # when the range is exactly a multiple of the std, the threshold is the range's over that multiple
    assert abs(equal_standing_threshold(sd, 3.0 * sd, 2.0) - 2.0 / 3.0) <= 0.01


def _pred(labels, modes, stat_std, in_domain=None):
    n = len(labels)
    return pd.DataFrame(
        {
            "label": labels,
            "label_fraction": np.ones(n),
            "mode": modes,
            "in_domain": in_domain if in_domain is not None else [True] * n,
            "stat_std": stat_std,
            "stat_range": np.asarray(stat_std) * 3,
        }
    )


def test_gated_table_counts_the_gate_against_moving_and_standing_windows():
    items = [{"subject": "A", "phone": "p", "motion": "Texting", "mode": "walk"}]
    p = _pred(
        ["walk", "walk", "walk", "still", "still", "still"],
        ["walk", "walk", "run", "walk", "walk", "walk"],
        [0.2, 0.8, 0.8, 0.1, 0.9, 0.9],
        [True, True, True, True, True, False],
    )
    t = gated_table(items, [p], "std", 0.5).iloc[0]
    # moving: one read still (wrong), one right, one run (wrong)
    assert (t["n"], t["right"], t["wrong"], t["as_still"], t["flagged"]) == (3, 1, 2, 1, 0)
    # standing: one read still, one read as a mode, one flagged
    assert (t["n_still"], t["still_moded"], t["still_flagged"]) == (3, 1, 1)
    # a per-person threshold: A's own
    t2 = gated_table(items, [p], "std", {"A": 0.1}).iloc[0]
    assert t2["right"] == 2 and t2["still_moded"] == 2
