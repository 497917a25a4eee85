"""IFSM (paper 000): hand-built state-transition sequences, fast == loop, paper Table 2/3 on the real data."""

import numpy as np
import pytest

from gaitml.recording import Recording
from gaitml.steps.ifsm import IFSM_READINGS, IFSMLiteralStepDetector, IFSMStepDetector, ifsm_steps
from tests.steps.reference_fsm import ifsm_steps_loop

IMPLS = [ifsm_steps, ifsm_steps_loop]
REPRO = dict(zip(("count_entry", "inclusive", "end_condition"), IFSM_READINGS["reproduce"], strict=True))
LITERAL = dict(zip(("count_entry", "inclusive", "end_condition"), IFSM_READINGS["literal"], strict=True))

FLAT = [9.0, 9.0]
UP4 = [10.0, 10.5, 11.0, 11.5]  # entry sample (10.0) + 3 climbs: 4 climbs when the entry counts
DOWN8 = [11.0, 10.5, 10.0, 9.5, 9.0, 8.5, 8.0, 7.5]
UP2 = [8.0, 8.5, 9.0, 9.5, 9.7, 9.8]  # 5th climb at 9.7 > A_T - delta = 9.61
TAIL = [9.0, 9.0, 9.0]


def seq(*parts):
    return np.concatenate([np.asarray(p, dtype=float) for p in parts])


@pytest.mark.parametrize("impl", IMPLS)
def test_full_step_every_state(impl):
    A = seq(FLAT, UP4, DOWN8, UP2, TAIL)
    ev = impl(A, **REPRO)
    # t0 = first sample above 9.81 (index 2), peak = 11.5 (5), trough = 7.5 (13), end = 9.7 (18)
    assert ev.tolist() == [[2, 5, 13, 18]]


@pytest.mark.parametrize("impl", IMPLS)
def test_s0_waits_below_threshold(impl):
    A = seq(FLAT, [9.5, 9.8, 9.7, 9.81, 9.2], TAIL)  # never strictly above A_T
    assert len(impl(A, **REPRO)) == 0


@pytest.mark.parametrize("impl", IMPLS)
def test_s1_noise_reset_then_recovers(impl):
    # climb, then 3 descents (T_dis) before a peak: back to s0; the following real step is still found
    noise = [10.0, 10.5, 10.4, 10.3, 10.2]
    A = seq(FLAT, noise, [9.0, 9.0], UP4, DOWN8, UP2, TAIL)
    ev = impl(A, **REPRO)
    assert len(ev) == 1
    assert ev[0, 0] == 2 + len(noise) + 2  # t0 of the real step, not of the noise


@pytest.mark.parametrize("impl", IMPLS)
def test_s1_needs_enough_climbs(impl):
    A = seq(FLAT, [10.0, 10.5, 11.0], DOWN8, UP2, TAIL)  # only 3 climbs: no peak state, the descent resets
    assert len(impl(A, **REPRO)) == 0


@pytest.mark.parametrize("impl", IMPLS)
def test_s3_short_descent_is_not_a_trough(impl):
    # 5 descents then a bump: the first minimum is not a trough (T_D = 7); 3 more descents make the next one a trough
    A = seq(FLAT, UP4, [11.0, 10.5, 10.0, 9.5, 9.0], [9.3], [8.8, 8.3, 7.8], UP2, TAIL)
    ev = impl(A, **REPRO)
    assert len(ev) == 1
    assert A[ev[0, 2]] == 7.8


@pytest.mark.parametrize("impl", IMPLS)
def test_s5_end_condition_recovered_vs_literal(impl):
    low_climb = [8.0, 8.5, 8.9, 9.1, 9.3, 9.5]  # 6 climbs but stays below A_T - delta
    A = seq(FLAT, [9.9], UP4, [12.0, 11.5], DOWN8, low_climb, [9.5, 9.4, 9.0], TAIL)
    assert len(impl(A, **REPRO)) == 0
    ev = impl(A, **LITERAL)  # literal end condition is always true: s6 after > 5 climbs
    assert len(ev) == 1 and A[ev[0, 3]] == 9.5


@pytest.mark.parametrize("impl", IMPLS)
def test_literal_does_not_count_the_entry_sample(impl):
    A = seq(FLAT, UP4, DOWN8, UP2, TAIL)
    assert len(impl(A, **LITERAL)) == 0  # 3 climbs after t0, literal needs > 4
    A2 = seq(FLAT, [10.0, 10.5, 11.0, 11.5, 12.0, 12.5], [12.0, 11.5], DOWN8, UP2, [10.0, 10.1], TAIL)
    assert len(impl(A2, **LITERAL)) == 1


def test_fast_equals_loop_on_random_signals():
    rng = np.random.default_rng(0)
    for reading in (REPRO, LITERAL):
        for _ in range(20):
            t = np.arange(3000) / 50
            A = 9.8 + 3 * np.sin(2 * np.pi * rng.uniform(1.2, 2.5) * t) + rng.normal(0, rng.uniform(0.05, 1.0), len(t))
            np.testing.assert_array_equal(ifsm_steps(A, **reading), ifsm_steps_loop(A, **reading))


def test_paper_table2_and_table3(ifsm_recs):
    r1, r2 = ifsm_recs
    s1 = IFSMStepDetector().detect(r1).steps_
    s2 = IFSMStepDetector().detect(r2).steps_
    assert abs(len(s1) - 284) <= 1 and abs(len(s2) - 319) <= 1
    manual = np.array([0.64, 0.56, 0.58, 0.50, 0.54, 0.50, 0.54, 0.52, 0.54, 0.50])
    assert np.abs(s1["period_s"].to_numpy()[:10] - manual).mean() <= 0.03
    assert s1.attrs["event"] == "t_end_s"
    lit = IFSMLiteralStepDetector().detect(r1).steps_
    assert len(lit) < 0.9 * 284  # the literal reading undercounts


def test_other_sampling_rate_is_resampled(ifsm_recs):
    r1 = ifsm_recs[0]
    t = np.arange(r1.n_samples) / 50.0
    t2 = np.arange(int(t[-1] * 100) + 1) / 100.0
    acc2 = np.column_stack([np.interp(t2, t, r1.acc[:, i]) for i in range(3)])
    s = IFSMStepDetector().detect(Recording.from_arrays(acc2, 100.0)).steps_
    assert abs(len(s) - 284) <= 3
    assert s["end"].max() <= len(t2)
