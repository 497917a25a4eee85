"""The floor rule of experiments/scripts/tyrex_steps_rates.py on count tables with known losses."""

from __future__ import annotations

import pandas as pd

from experiments.scripts.tyrex_steps_rates import NATIVE_FLOOR_HZ, SCORED, choose_floor, lopo_floors, per_motion, worst_drop

RATES = [50.0, 30.0, 20.0, 10.0]


def _table(loss: dict[str, dict[float, float]]) -> pd.DataFrame:
    """Three people x the scored motions, 100 reference steps, a detector 'd' exact at native and losing
    ``loss[person][rate]`` of the steps at each rate (0 where not given)."""
    rows = []
    for person in ("A", "B", "C"):
        for motion in SCORED:
            row = {"recording": f"{person}_{motion}", "motion": motion, "person": person, "mocap_steps": 100, "d @ native": 100}
            for r in RATES:
                row[f"d @ {r:g} Hz"] = round(100 * (1 - loss.get(person, {}).get(r, 0.0)))
            rows.append(row)
    rows.append({**rows[0], "motion": "AR", "d @ 10 Hz": 0})  # AR is not scored
    return pd.DataFrame(rows)


def test_the_floor_is_the_lowest_rate_that_and_every_rate_above_it_hold():
    df = _table({p: {10.0: 0.2} for p in "ABC"})
    acc = per_motion(df)
    assert worst_drop(acc, "d", 20.0) == 0.0 and abs(worst_drop(acc, "d", 10.0) - 0.2) < 1e-9
    assert choose_floor(acc, "d", RATES) == 20.0
    # a loss at 30 Hz stops the walk down even though 20 Hz holds again
    df = _table({p: {30.0: 0.1, 10.0: 0.2} for p in "ABC"})
    assert choose_floor(per_motion(df), "d", RATES) == 50.0
    # a loss within the allowance does not
    assert choose_floor(per_motion(_table({p: {10.0: 0.04} for p in "ABC"})), "d", RATES) == 10.0
    # a loss already at the highest rate: the phones' own rate
    assert choose_floor(per_motion(_table({p: {50.0: 0.3} for p in "ABC"})), "d", RATES) == NATIVE_FLOOR_HZ


def test_leave_one_person_out_scores_the_floor_on_the_person_left_out():
    # only person C loses at 10 Hz, and by 0.3: chosen without C the floor is 10 Hz, and C's drop there is 0.3
    lo = lopo_floors(_table({"C": {10.0: 0.3}}), ["d"], RATES).set_index("left out")
    assert lo.loc["C", "floor chosen (Hz)"] == 10.0 and abs(lo.loc["C", "drop at floor (held out)"] - 0.3) < 1e-9
    assert lo.loc["C", "own floor (Hz)"] == 20.0
    assert lo.loc["A", "floor chosen (Hz)"] == 20.0 and lo.loc["A", "drop at floor (held out)"] == 0.0
    # in sample the mean over the three people loses 0.1 at 10 Hz: above the allowance
    assert lo.loc["all", "floor chosen (Hz)"] == 20.0
