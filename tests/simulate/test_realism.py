"""Realism against the real flat-held walks (../shared/data/ifsm-flat-phone) and variation across subjects."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.simulate import sample_subjects, simulate_recording
from gaitml.simulate.realism import gait_statistics, real_statistics, realism_table, reference_walk
from tests.conftest import shared

pytestmark = pytest.mark.realdata


@pytest.fixture(scope="module")
def real_stats():
    return real_statistics(shared())


def test_statistics_find_the_published_steps_in_the_real_files(real_stats):
    # paper 000 Table 2: 284 and 319 true steps
    assert [s["n_peaks"] for s in real_stats] == [284, 319]


def test_simulated_flat_walk_inside_real_range():
    tab = realism_table(shared())
    assert tab.loc["mag_mean_ms2", "simulated"] == pytest.approx(9.8, abs=0.3)
    assert tab["inside"].all(), tab.to_string()


@pytest.mark.parametrize("seed", [1, 2])
def test_other_seeds_stay_inside_real_range(seed):
    tab = realism_table(shared(), simulated=reference_walk(seed=seed))
    assert tab["inside"].all(), tab.to_string()


def test_variation_across_subjects_spans_the_real_walkers(real_stats):
    sims = [
        gait_statistics(simulate_recording(s, modes=("walk",), duration_s=60.0, seed=i)) for i, s in enumerate(sample_subjects(8, seed=0))
    ]
    for key in ("cadence_hz", "mag_std_ms2"):
        spread = np.ptp([s[key] for s in sims])
        real_diff = abs(real_stats[0][key] - real_stats[1][key])
        assert spread >= real_diff, (key, spread, real_diff)
    # and stays human: every simulated walker in a plausible band
    assert all(1.6 < s["cadence_hz"] < 2.3 for s in sims)
    assert all(9.5 < s["mag_mean_ms2"] < 10.2 for s in sims)


def test_realism_main_prints_the_table(capsys):
    from gaitml.simulate.realism import main

    rc = main([str(shared())])
    out = capsys.readouterr().out
    assert rc == 0
    assert "real_1" in out and "simulated" in out and "cadence_hz" in out
