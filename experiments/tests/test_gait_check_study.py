"""experiments.scripts.gait_check_study: the context count and the rejection rule the selection grid applies."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.gait_check_study import bout_context, grid_rejects


def _bouts() -> pd.DataFrame:
    # one recording: a 6-step bout, a 20-step walk 10 s later, a 5-step bout 60 s after that
    return pd.DataFrame(
        {
            "rec": ["a"] * 3,
            "t_start_s": [0.0, 12.5, 82.0],
            "t_end_s": [2.5, 22.0, 84.0],
            "n_steps": [6, 20, 5],
            "rot": [False, False, False],
            "vfrac": [0.1, 0.1, 0.9],
        }
    )


def test_context_counts_the_other_bouts_within_the_window():
    d = _bouts()
    assert bout_context(d, ["rec"], 30.0).tolist() == [20, 6, 0]
    assert bout_context(d, ["rec"], 5.0).tolist() == [0, 0, 0]


def test_rejects_combines_the_vertical_test_and_the_context_rule():
    d = _bouts()
    d["ctx"] = bout_context(d, ["rec"], 30.0)
    assert grid_rejects(d, np.inf, 0).tolist() == [False, False, False]
    assert grid_rejects(d, 0.4, 0).tolist() == [False, False, True]  # the stroke-like bout
    assert grid_rejects(d, np.inf, 20).tolist() == [False, False, True]  # the lone short bout
    assert grid_rejects(d, np.inf, 30).tolist() == [True, False, True]  # 6 + 20 < 30: the short bout near the walk too
