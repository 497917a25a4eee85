"""Lab tests of the walking-episode bout rule's leave-one-person-out script (small, synthetic)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.tyrex_steps_bouts import GRID, OFF, admissible_set, bout_of, choose, dropped_bouts, grid_of, lopo
from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED


def test_the_grids_are_the_ones_fixed_before_measuring():
    for r, walk in ((1, 0), (2, 10), (3, 10)):
        g = grid_of(r)
        # off is today's rules spelled out (stage 5b off whatever adaptive's defaults)
        assert len(g) == 9 and g[OFF] == {"episode_gap_ratio": 0.0}
        assert {v["episode_walk_steps"] for k, v in g.items() if k != OFF} == {walk}
        # rounds 1-2 ran stage 5b before the gait check, round 3 after it
        assert {v["episode_before_gait_check"] for k, v in g.items() if k != OFF} == {r < 3}
        assert {(v["episode_gap_ratio"], v["max_bout_interval_cv"]) for k, v in g.items() if k != OFF} == {
            (3.0, 0.1),
            (3.0, 0.2),
            (5.0, 0.1),
            (5.0, 0.2),
        }
    assert len(GRID) == 25  # off once, eight per round


def _rates(g, d, gc=0.1, dc=0.5):
    return {"gestures": g, "desk": d, "gestures_confident": gc, "desk_confident": dc}


def test_admissible_needs_no_more_raw_and_no_more_confident_non_gait_steps():
    rates = {OFF: _rates(1.0, 3.0), "a": _rates(1.0, 2.9), "b": _rates(1.1, 2.0), "c": _rates(0.5, 2.0, dc=0.6)}
    assert admissible_set(rates) == {OFF, "a"}


def _grid(gain: dict[str, float]) -> dict[str, pd.DataFrame]:
    """A frame per setting: every person and motion at 0.9 (running 0.96), plus ``gain[setting]`` for every person
    but the last; the last person loses it instead."""
    out = {}
    for k in [OFF, *gain]:
        rows = []
        for i, p in enumerate(PEOPLE):
            for m in SCORED:
                base = 0.96 if m.startswith("Running") else 0.9
                g = gain.get(k, 0.0)
                rows.append(
                    {
                        "recording": f"{p}{m}",
                        "motion": m,
                        "person": p,
                        "n": 1,
                        "acc": base + (g if i < 2 else -g),
                        "hits": 1,
                        "extras": 0,
                        "misses": 0,
                    }
                )
        out[k] = pd.DataFrame(rows)
    return out


def test_choose_prefers_off_on_ties_and_never_an_inadmissible_setting():
    g = _grid({"G3,C0.1": 0.0, "G3,C0.2": 0.03})
    assert choose(g, {OFF, "G3,C0.1"}) == OFF
    assert choose(g, {OFF}) == OFF
    assert choose(g, {OFF, "G3,C0.2"}, people=PEOPLE[:2]) == "G3,C0.2"


def test_lopo_fails_when_the_setting_chosen_on_two_costs_the_third():
    g = _grid({"G3,C0.2": 0.03})
    _, checks, chosen = lopo(g, set(g))
    assert chosen[-1] == "G3,C0.2"  # chosen on the first two people, who gain
    assert not checks["B2"]  # the third loses 0.03


def test_lopo_passes_a_setting_better_for_everyone():
    g = _grid({"G3,C0.2": 0.0})
    g["G3,C0.2"]["acc"] = g["G3,C0.2"]["acc"] + 0.02
    _, checks, chosen = lopo(g, set(g))
    assert chosen == ["G3,C0.2"] * 3
    assert checks == {"B1": True, "B2": True, "B3": True}


def test_bout_of_splits_at_two_periods():
    t = np.array([0.0, 0.5, 1.0, 2.2, 2.7])
    assert bout_of(t, np.full(5, 0.5)).tolist() == [0, 0, 0, 1, 1]


def test_dropped_bouts_describes_the_bouts_with_no_kept_step():
    period = np.full(9, 0.5)
    t_all = np.r_[np.arange(5) * 0.5, 3.5, 4.0, 4.5, 20.0]  # a walk, a 3-step bout 3 periods after it, a lone step
    kept = t_all[:5]
    ref = np.r_[np.arange(5) * 0.5, 3.5, 4.0]
    d = dropped_bouts(t_all, period, np.full(9, 0.3), kept, ref)
    assert d["steps"].tolist() == [3, 1]
    assert d["matched"].tolist() == [2, 0]
    assert d["interval_cv"].iloc[0] == pytest.approx(0.0)
    assert d["gap_periods"].iloc[0] == pytest.approx(3.0)  # 3.5 s - 2.0 s = 1.5 s = 3 periods
    assert np.isinf(d["interval_cv"].iloc[1])
