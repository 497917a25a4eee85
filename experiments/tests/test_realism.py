"""The realism study (experiments/scripts/realism.py): its peak counter on simulated walks, the simulator against the real
flat-held walks (../shared/data/ifsm-flat-phone), and variation across subjects."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.realism import (
    count_peaks,
    gait_statistics,
    real_statistics,
    real_window_variability,
    realism_table,
    reference_walk,
    simulated_walkers,
    variability_table,
    window_variability,
)
from experiments.tests.conftest import shared
from gaitml.simulate import Subject, sample_subjects, simulate_recording

realdata = pytest.mark.realdata


def _single(mode, subject, duration_s=40.0, seed=0, **kw):
    return simulate_recording(subject, modes=(mode,), duration_s=duration_s, seed=seed, **kw)


@pytest.fixture(scope="module")
def real_stats():
    return real_statistics(shared())


@realdata
def test_statistics_find_the_published_steps_in_the_real_files(real_stats):
    # paper 000 Table 2: 284 and 319 true steps
    assert [s["n_peaks"] for s in real_stats] == [284, 319]


@realdata
def test_simulated_flat_walk_inside_real_range():
    tab = realism_table(shared())
    assert tab.loc["mag_mean_ms2", "simulated"] == pytest.approx(9.8, abs=0.3)
    assert tab["inside"].all(), tab.to_string()


@realdata
@pytest.mark.parametrize("seed", [1, 2])
def test_other_seeds_stay_inside_real_range(seed):
    tab = realism_table(shared(), simulated=reference_walk(seed=seed))
    assert tab["inside"].all(), tab.to_string()


@realdata
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


@realdata
def test_realism_main_prints_the_table(capsys):
    from experiments.scripts.realism import main

    rc = main([str(shared())])
    out = capsys.readouterr().out
    assert rc == 0
    assert "real_1" in out and "simulated" in out and "cadence_hz" in out


@pytest.fixture(scope="module")
def variability():
    return variability_table(shared(), simulated=simulated_walkers(4, seed=0, duration_s=120.0))


@realdata
def test_real_window_variability_is_measured():
    real = real_window_variability(shared())
    # the two real walks: window-variance CV about 0.22-0.23 at 0.5 s, 0.15-0.19 at 1.5 s
    for r in real:
        assert 0.15 < r["cv_acc_mag__var_0.5s"] < 0.35
        assert r["cv_acc_mag__var_1.5s"] < r["cv_acc_mag__var_0.5s"]


@realdata
def test_window_variance_cv_matches_real_walks(variability):
    # step-to-step variability: the CV across windows of the window variance of |acc|
    for length in ("0.5s", "1.5s"):
        row = variability.loc[f"cv_acc_mag__var_{length}"]
        assert row["inside"], variability.to_string()
        assert row["near"], variability.to_string()


@realdata
def test_window_max_min_cv_near_real_walks(variability):
    assert variability["near"].all(), variability.to_string()


@realdata
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


def _peak_height(s: Subject, mode: str) -> float:
    """Paper 003's 2 m/s^2 above g, scaled by the hand gain for the damped modes: a calm walker's
    steps (gain 0.25-1.2) stay below a fixed 2 m/s^2, as the calmest real Oxford InHand walks do."""
    return 2.0 * (1.0 if mode == "run" else min(1.0, s.hand_gain))


@pytest.mark.parametrize("mode", ["walk", "run"])
def test_peak_counting_recovers_true_steps(mode):
    for i, s in enumerate(sample_subjects(4, seed=11)):
        rec = simulate_recording(s, modes=(mode,), duration_s=60.0, seed=i)
        n_true = rec.reference["n_steps_true"]
        n_found = len(count_peaks(rec, height_above_g_ms2=_peak_height(s, mode)))
        assert abs(n_found - n_true) <= 0.02 * n_true, (s.subject, s.hand_gain, n_found, n_true)


@pytest.mark.parametrize("mode", ["walk", "run", "side_left", "side_right", "backward"])
def test_peak_times_match_true_step_times(mode):
    rec = _single(mode, Subject(), duration_s=40.0)
    pk = count_peaks(rec) / rec.sampling_rate_hz
    t_true = rec.reference["steps_t_s"]
    d = np.abs(pk[:, None] - t_true[None, :]).min(axis=1)
    assert np.median(d) <= 1.0 / rec.sampling_rate_hz + 1e-9
    assert np.percentile(d, 95) < 0.06


@pytest.mark.parametrize(("pose", "fs"), [("tilted", 100.0), ("flat", 200.0)])
def test_peak_counting_other_poses_and_rates(pose, fs):
    for i, s in enumerate(sample_subjects(2, seed=12, pose=pose)):
        for mode in ("walk", "run"):
            rec = simulate_recording(s, modes=(mode,), duration_s=30.0, seed=i, sampling_rate_hz=fs)
            n_true = rec.reference["n_steps_true"]
            assert abs(len(count_peaks(rec, height_above_g_ms2=_peak_height(s, mode))) - n_true) <= 0.02 * n_true, (s.hand_gain, mode)
    assert s.pose == pose
