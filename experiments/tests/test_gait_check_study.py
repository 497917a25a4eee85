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


def test_only_bouts_that_stand_on_their_own_are_context():
    """As the library counts it: three 7-step runs 8 s apart do not confirm one another; a walk does."""
    from experiments.scripts.gait_check_study import standing_bouts

    runs = pd.DataFrame(
        {
            "rec": ["a"] * 3,
            "t_start_s": [60.0, 68.0, 76.0],
            "t_end_s": [63.0, 71.0, 79.0],
            "n_steps": [7, 7, 7],
            "rot": [False] * 3,
            "vfrac": [0.1] * 3,
        }
    )
    assert bout_context(runs, ["rec"], 30.0).tolist() == [14, 14, 14]  # every bout counted: 7 + 14 >= 20
    runs["ctx"] = bout_context(runs, ["rec"], 30.0, standing_bouts(runs, 0.4))
    assert runs["ctx"].tolist() == [0, 0, 0]
    assert grid_rejects(runs, 0.4, 20).tolist() == [True, True, True]
    d = _bouts()  # the 20-step walk stands on its own; the stroke-like 5-step bout would not
    assert bout_context(d, ["rec"], 30.0, standing_bouts(d, 0.4)).tolist() == [20, 0, 0]
