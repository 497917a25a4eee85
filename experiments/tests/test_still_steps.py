"""Lab: the step-veto study's counting, threshold criterion and adoption rule (experiments/scripts/still_steps.py)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.still_steps import adoption_checks, step_counts, vetoed, vetoed_standing_threshold


def test_steps_are_counted_inside_and_within_half_a_second():
    w = pd.DataFrame({"start": [0, 75, 150], "end": [75, 150, 225]})
    c = step_counts(np.array([10, 74, 80, 170]), w, 50.0)
    np.testing.assert_array_equal(c["in"], [2, 1, 1])
    np.testing.assert_array_equal(c["near"], [3, 3, 1])  # 25 samples of reach at 50 Hz
    np.testing.assert_array_equal(vetoed(c, ">=2 in"), [True, False, False])
    np.testing.assert_array_equal(vetoed(c, ">=2 +-0.5 s"), [True, True, False])


def test_the_vetoed_threshold_reads_as_many_standing_windows_still_as_the_range_rule():
    sd = np.linspace(0.01, 1.0, 100)
    rg = np.where(np.arange(100) < 70, 1.0, 3.0)  # the range rule reads 70 % still
    veto = np.zeros(100, dtype=bool)
    assert vetoed_standing_threshold(sd, rg, veto, 2.0) == 0.71  # the 70th smallest std is 0.70: read below 0.71
    veto[:10] = True  # ten of the calmest are vetoed: the threshold must reach ten further to read 70 still
    t = vetoed_standing_threshold(sd, rg, veto, 2.0)
    assert t == 0.81 and np.sum((sd < t) & ~veto) == 70
    veto[:50] = True  # fewer free windows than the range rule reads still: no threshold can match it
    assert np.isnan(vetoed_standing_threshold(sd, rg, veto, 2.0))


def _tables(wrong: dict, moded: int):
    t = pd.DataFrame([{"motion": m, "n": 100, "wrong": w, "still_moded": 0, "n_still": 50} for m, w in wrong.items()])
    t.loc[0, "still_moded"] = moded
    return None, t


def test_the_adoption_rule_wants_phoning_down_and_nothing_else_up():
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    base = dict.fromkeys(MOTION_ORDER, 2)
    before = {"50": _tables(base, 10)}
    table = {"50": {"phone lying on a table": 1.0, "simulate_nongait desk": 0.8, "gestures": 0.4}}
    ok, _ = adoption_checks(before, {"50": _tables({**base, "Phoning": 1}, 10)}, table, table)
    assert ok
    # Phoning not falling, another motion rising, standing rising by more than 0.02, the desk falling: each fails
    assert not adoption_checks(before, {"50": _tables(base, 10)}, table, table)[0]
    assert not adoption_checks(before, {"50": _tables({**base, "Phoning": 1, "AR": 3}, 10)}, table, table)[0]
    assert adoption_checks(before, {"50": _tables({**base, "Phoning": 1}, 18)}, table, table)[0]  # +0.02 of 400
    assert not adoption_checks(before, {"50": _tables({**base, "Phoning": 1}, 20)}, table, table)[0]
    worse = {"50": {**table["50"], "simulate_nongait desk": 0.77}}
    assert not adoption_checks(before, {"50": _tables({**base, "Phoning": 1}, 10)}, table, worse)[0]
    gestures = {"50": {**table["50"], "gestures": 0.1}}  # gestures are reported, not ruled on
    assert adoption_checks(before, {"50": _tables({**base, "Phoning": 1}, 10)}, table, gestures)[0]
