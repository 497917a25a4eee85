"""Lab: the still_unsure study's candidates, scorer and rule (experiments.scripts.still_flag), and the tyrex scorer's flag."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.still_flag import adoption, candidate_marks, score_table
from experiments.scripts.tyrex_modes import flagged_windows, score_windows


def _rows() -> pd.DataFrame:
    # Phoning: 10 moving windows, 4 reported still (2 with the rhythm, 1 of them with a step); 4 standing, 2 with the rhythm
    n = 14
    still = np.array([1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1], dtype=bool)
    rhythm = np.array([1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0], dtype=bool)
    steps = np.array([1, 0, 0, 0, np.nan, np.nan, np.nan, np.nan, np.nan, np.nan, 0, 0, 0, 0], dtype=float)
    label = np.array(["walk"] * 10 + ["still"] * 4, dtype=object)
    mode = np.where(still, "still", "walk")
    return pd.DataFrame(
        {
            "who": "Jakob",
            "motion": "Phoning",
            "true_mode": "walk",
            "label": label,
            "label_fraction": np.ones(n),
            "mode": mode,
            "flagged": np.zeros(n, dtype=bool),
            "still": still,
            "window_steps": steps,
            "rhythm": rhythm,
            "still_unsure": still & rhythm,
        }
    )


def test_candidates_mark_only_still_windows():
    r = _rows()
    m = candidate_marks(r["still"], r["rhythm"], r["window_steps"])
    assert not m["baseline"].any()
    assert m["rhythm"].sum() == 4 and not (m["rhythm"] & ~r["still"].to_numpy()).any()
    assert m["rhythm+step"].sum() == 1  # one step inside (NaN counts as none)


def test_a_marked_window_is_flagged_not_wrong_and_the_rule_reads_it():
    r = _rows()
    base, cand = score_table(r, "baseline"), score_table(r, "rhythm")
    b = base[(base["motion"] == "Phoning") & (base["who"] == "all")].iloc[0]
    c = cand[(cand["motion"] == "Phoning") & (cand["who"] == "all")].iloc[0]
    assert (b["right"], b["flagged"], b["wrong"]) == (6, 0, 4)
    assert (c["right"], c["flagged"], c["wrong"]) == (6, 2, 2)
    assert c["standing marked"] == 2 and c["standing as a mode"] == 0
    ok, checks = adoption(base, cand, 50.0)
    # Phoning 2 of 10 still silently wrong (> 0.05) and half the standing windows marked (> 0.15): both fail
    assert not ok
    failed = set(checks.loc[~checks["pass"], "check"])
    assert failed == {"R1 Phoning silently wrong", "R4 standing windows marked unsure"}


def test_the_tyrex_scorer_counts_still_unsure_as_flagged():
    p = pd.DataFrame(
        {
            "label": ["walk"] * 3,
            "label_fraction": [1.0] * 3,
            "mode": ["walk", "still", "still"],
            "in_domain": np.array([True, True, True], dtype=object),
            "still_unsure": [False, True, False],
        }
    )
    np.testing.assert_array_equal(flagged_windows(p), [False, True, False])
    s = score_windows(p, "walk")
    assert (s["right"], s["flagged"], s["wrong"], s["as_still"]) == (1, 1, 1, 1)
    s_old = score_windows(p.drop(columns="still_unsure"), "walk")  # a table without the column: the domain flag alone
    assert (s_old["flagged"], s_old["wrong"]) == (0, 2)
