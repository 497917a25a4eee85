"""The leave-one-person-out adoption checks and the per-step matching of experiments/scripts/tyrex_steps_octave.py."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED
from experiments.scripts.tyrex_steps_octave import OFF, lopo, match_steps


def _grid(delta: dict[str, dict[str, float]]) -> pd.DataFrame:
    """Two recordings per person and motion, count accuracy 0.9 plus ``delta[person][motion]``."""
    rows = [
        {"recording": f"{p}-{m}-{i}", "motion": m, "person": p, "n": 0, "acc": 0.9 + delta.get(p, {}).get(m, 0.0)}
        for p in PEOPLE
        for m in SCORED
        for i in range(2)
    ]
    return pd.DataFrame(rows)


def test_a_setting_better_for_everyone_passes_the_tyrex_checks():
    up = {p: {"Texting": 0.05, "Phoning": 0.02} for p in PEOPLE}
    _, checks, _ = lopo({OFF: _grid({}), (0.5, 0.0): _grid(up)})
    assert checks == {"A1": True, "A2": True, "A3": True}


def test_a_setting_that_helps_two_people_and_hurts_the_third_fails():
    # chosen on Jakob and Thibaud (it helps them), it costs Guillaume 0.05 on Texting: A1 and A3 fail
    d = {"Jakob": {"Texting": 0.05}, "Thibaud": {"Texting": 0.05}, "Guillaume": {"Texting": -0.05}}
    table, checks, _ = lopo({OFF: _grid({}), (0.5, 0.0): _grid(d)})
    assert checks["A1"] is False and checks["A3"] is False
    assert "| Guillaume | 0.5, 0 |" in table


def test_matching_counts_each_reference_step_once():
    ref = np.array([1.0, 2.0, 3.0, 4.0])
    assert match_steps(np.array([1.1, 1.2, 2.9, 6.0]), ref) == (2, 2, 2)  # 1.2 is a second step near 1.0: an extra
    assert match_steps(np.array([]), ref) == (0, 0, 4)
