"""The hand-gain study (experiments/scripts/hand_gain.py): its range fit, and the shipped range against real walks."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.simulate.subject import HAND_GAIN_RANGE


def test_fit_range_recovers_a_known_range_from_synthetic_curves():
    from experiments.scripts.hand_gain import GAIN_GRID, fit_range

    rng = np.random.default_rng(0)
    # mag_std proportional to the gain, subject factors 2.7-4.0 (the simulated hand-held spread)
    factors = rng.uniform(2.7, 4.0, 40)
    curves = factors[:, None] * GAIN_GRID[None, :]
    # the target from an independent Monte-Carlo population: random subjects at log-uniform gains
    n = 20000
    gains = np.exp(rng.uniform(np.log(0.4), np.log(1.1), n))
    target = np.percentile(rng.choice(factors, n) * gains, [5, 95])
    lo, hi = fit_range(np.array(target), curves)
    assert abs(lo - 0.4) <= 0.05 and abs(hi - 1.1) <= 0.05


#: How far the ends of the simulated population's 5-95 % range of ``mag_std`` may lie from the real walks' (m/s^2):
#: a population much wider than the real walkers would cover them without being like them.
SPREAD_MARGIN_MS2 = 0.75


@pytest.mark.realdata
@pytest.mark.slow
def test_the_shipped_range_gives_walkers_like_every_real_hand_held_user(shared_data):
    """New simulated walkers drawn from HAND_GAIN_RANGE span the real hand-held walks of all five users (the
    statistic ``python -m experiments.scripts.hand_gain`` fits the range on), within the lab's tolerance."""
    from experiments.scripts.hand_gain import check_population, covered, real_hand_walks

    walks = real_hand_walks(shared_data)
    assert sorted(walks["user"].unique()) == ["Carmelo", "Dario", "Jamie", "ifsm-1", "ifsm-2"]
    sim = check_population(*HAND_GAIN_RANGE)
    assert covered(walks, sim)["mag_std_ms2"] >= 0.9
    ends = np.percentile(sim["mag_std_ms2"], [5, 95]) - [walks["mag_std_ms2"].min(), walks["mag_std_ms2"].max()]
    assert np.all(np.abs(ends) <= SPREAD_MARGIN_MS2), ends
