"""The carry-vigour study (experiments/scripts/carry_vigour.py): where the vigour is drawn, and the shipped ranges\nagainst real walks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.stats

from gaitml.simulate import Placement
from gaitml.simulate.positions import CARRIED_POSITIONS, VIGOUR_RANGE

#: How far the ends of the simulated population's 5-95 % range of ``mag_std`` may lie from the real walks' (m/s^2).
SPREAD_MARGIN_MS2 = 0.75


def test_vigour_is_drawn_last_and_only_where_it_was_fitted():
    from experiments.scripts.carry_vigour import VIGOUR_POSITIONS, vigour_range

    assert set(VIGOUR_RANGE) == set(VIGOUR_POSITIONS)
    for position in CARRIED_POSITIONS:
        drawn = [Placement.random(position, np.random.default_rng(s)) for s in range(2000)]
        v = np.array([p.vigour for p in drawn])
        if position not in VIGOUR_RANGE:
            assert np.all(v == 1.0), position
            continue
        lo, hi = VIGOUR_RANGE[position]
        assert v.min() >= lo and v.max() <= hi
        if hi > lo:  # log-uniform, not uniform: the logs are uniform over the range's logs
            span = np.log(hi) - np.log(lo)
            assert scipy.stats.kstest(np.log(v), "uniform", args=(np.log(lo), span)).pvalue > 0.01
            if hi / lo > 1.5:  # wide enough to tell log-uniform from uniform (not the bag's 0.95-1.10)
                assert scipy.stats.kstest(v, "uniform", args=(lo, hi - lo)).pvalue < 1e-6
        with vigour_range(position, 1.3, 1.3):
            again = Placement.random(position, np.random.default_rng(7))
        assert again.vigour == pytest.approx(1.3)
        assert dataclasses.replace(again, vigour=drawn[7].vigour) == drawn[7]


@pytest.mark.realdata
@pytest.mark.slow
def test_the_shipped_ranges_give_walkers_like_every_real_oxford_user(shared_data):
    """New simulated walkers drawn from VIGOUR_RANGE span the real walks of the three Oxford users in every
    carried position the vigour was fitted for, within the lab's tolerance (as for the hand gain)."""
    from experiments.scripts.carry_vigour import VIGOUR_POSITIONS, check_population, real_carried_walks
    from experiments.scripts.hand_gain import covered

    walks = real_carried_walks(shared_data)
    for position in VIGOUR_POSITIONS:
        pw = walks[walks["position"] == position]
        assert sorted(pw["user"].unique()) == ["Carmelo", "Dario", "Jamie"], position
        sim = check_population(position, *VIGOUR_RANGE[position])
        assert covered(pw, sim, {"mag_std_ms2": 0.3})["mag_std_ms2"] >= 0.9, position
        ends = np.percentile(sim["mag_std_ms2"], [5, 95]) - [pw["mag_std_ms2"].min(), pw["mag_std_ms2"].max()]
        assert np.all(np.abs(ends) <= SPREAD_MARGIN_MS2), (position, ends)
