"""Realism against the real flat-held walks (../shared/data/ifsm-flat-phone) and variation across subjects."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.realism import (
    gait_statistics,
    real_statistics,
    real_window_variability,
    realism_table,
    reference_walk,
    simulated_walkers,
    variability_table,
    window_variability,
)
from gaitml.simulate import sample_subjects, simulate_recording
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
    from experiments.scripts.realism import main

    rc = main([str(shared())])
    out = capsys.readouterr().out
    assert rc == 0
    assert "real_1" in out and "simulated" in out and "cadence_hz" in out


@pytest.fixture(scope="module")
def variability():
    return variability_table(shared(), simulated=simulated_walkers(4, seed=0, duration_s=120.0))


def test_real_window_variability_is_measured():
    real = real_window_variability(shared())
    # the two real walks: window-variance CV about 0.22-0.23 at 0.5 s, 0.15-0.19 at 1.5 s
    for r in real:
        assert 0.15 < r["cv_acc_mag__var_0.5s"] < 0.35
        assert r["cv_acc_mag__var_1.5s"] < r["cv_acc_mag__var_0.5s"]


def test_window_variance_cv_matches_real_walks(variability):
    # step-to-step variability: the CV across windows of the window variance of |acc|
    for length in ("0.5s", "1.5s"):
        row = variability.loc[f"cv_acc_mag__var_{length}"]
        assert row["inside"], variability.to_string()
        assert row["near"], variability.to_string()


def test_window_max_min_cv_near_real_walks(variability):
    assert variability["near"].all(), variability.to_string()


def test_variability_comes_from_the_step_to_step_model():
    # without the per-half-step amplitude/shape/lateral variation, the speed drift and the hand-shake
    # drift (only step-time/length jitter, whose speed change sets the amplitude) windows are too alike
    import dataclasses

    from gaitml.simulate import Subject, simulate_recording

    steady = dataclasses.replace(
        Subject(), step_amp_cv=0.0, step_shape_cv=0.0, step_lateral_cv=0.0, speed_drift_cv=0.0, hand_jitter_drift=0.0
    )
    cv_steady = window_variability(simulate_recording(steady, modes=("walk",), duration_s=90.0, seed=0))
    cv_var = window_variability(simulate_recording(Subject(), modes=("walk",), duration_s=90.0, seed=0))
    assert cv_steady["cv_acc_mag__var_0.5s"] < 0.85 * cv_var["cv_acc_mag__var_0.5s"]
    assert cv_steady["cv_acc_mag__var_1.5s"] < 0.7 * cv_var["cv_acc_mag__var_1.5s"]
