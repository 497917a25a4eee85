"""Self-learning FSM (paper 002 sec. 2): every transition, noise paths, learning rule, segments, real data."""

import numpy as np
import pytest

from gaitml.steps.fsm_selflearn import ALPHA, BETA, SelfLearningFSMStepDetector, selflearn_fsm_run

TH = (10.3, 10.4, 9.3, 9.4)  # paper 002 Table 1
STEP = [10.35, 11.0, 10.0, 9.0, 9.35, 9.6]  # S1, S2, S3, S4, S5, S6
LEAD = [9.8, 9.8]
END = [10.5]  # > Thr: S7
TAIL = [9.8] * 3


def run(a, jump, **kw):
    kw.setdefault("max_step_samples", 1000)
    kw.setdefault("end_timeout_samples", 1000)
    ev, th, hist = selflearn_fsm_run(np.asarray(a, dtype=float), TH, jump=jump, **kw)
    return ev


@pytest.fixture(params=[True, False], ids=["jump", "loop"])
def jump(request):
    return request.param


def test_full_step_through_all_states(jump):
    ev = run(LEAD + STEP + END + TAIL, jump)
    # S1 entry 2, S2 entry 3, S4 entry 5, S7 at 8
    assert ev.tolist() == [[2, 3, 5, 8]]


def test_s0_stays_static(jump):
    assert len(run([9.8] * 20 + [10.2, 10.25] + [9.8] * 5, jump)) == 0


def test_s1_noise_reset_to_s0(jump):
    # above Thr but never above Thrpp, then below Thrneg: back to S0, no step
    assert len(run(LEAD + [10.35, 10.38, 9.0] + TAIL, jump)) == 0
    # and the next real step is found with its own start
    ev = run(LEAD + [10.35, 9.0] + LEAD + STEP + END + TAIL, jump)
    assert ev[:, 0].tolist() == [6]


def test_s3_back_to_s2_on_second_peak(jump):
    a = LEAD + [10.35, 11.0, 10.0, 11.2, 10.0, 9.0, 9.35, 9.6] + END + TAIL
    ev = run(a, jump)
    assert ev.tolist() == [[2, 3, 7, 10]]  # one step, its trough entry after the second peak


def test_s5_noise_tolerance_back_to_s4(jump):
    a = LEAD + [10.35, 11.0, 10.0, 9.0, 9.35, 9.1, 9.35, 9.6] + END + TAIL
    ev = run(a, jump)
    assert ev.tolist() == [[2, 3, 5, 10]]


def test_s6_back_to_s4(jump):
    a = LEAD + [10.35, 11.0, 10.0, 9.0, 9.35, 9.6, 9.0, 9.35, 9.6] + END + TAIL
    ev = run(a, jump)
    assert ev.tolist() == [[2, 3, 5, 11]]


def test_s7_chains_into_next_step(jump):
    a = LEAD + STEP + [10.35] + STEP[1:] + END + TAIL  # the S7 sample (10.35 > Thr) is the next step's S1
    ev = run(a, jump)
    assert ev[:, 0].tolist() == [2, 8] and ev[:, 3].tolist() == [8, 14]


def test_max_step_timeout_resets(jump):
    a = LEAD + [10.35] + [11.0] * 30 + [10.0, 9.0, 9.35, 9.6] + END + TAIL
    # too long in S2: reset to S0 at sample 22; the plateau is still above Thr, so a new step starts at 23
    assert run(a, jump, max_step_samples=20)[:, 0].tolist() == [23]
    assert run(a, jump, max_step_samples=100)[:, 0].tolist() == [2]
    assert len(run(LEAD + [10.35] + [11.0] * 30 + TAIL, jump, max_step_samples=20)) == 0


def test_s6_end_timeout_closes_the_last_step(jump):
    a = LEAD + STEP + [9.8] * 30
    ev = run(a, jump, end_timeout_samples=5)
    assert ev.tolist() == [[2, 3, 5, 7 + 5]]
    assert len(run(a, jump, end_timeout_samples=100)) == 0


def test_equal_to_threshold_is_not_above(jump):
    assert len(run(LEAD + [10.3, 10.3, 9.8] + TAIL, jump)) == 0


def test_learning_rule_eqs_2_3():
    a = np.asarray(LEAD + STEP + END + TAIL)
    ev, th, hist = selflearn_fsm_run(a, TH, max_step_samples=1000, end_timeout_samples=1000, learn=True, learn_steps=1)
    max_i, min_i = 11.0, 9.0  # first step: max_h = max_i, min_h = min_i
    assert th[1] == pytest.approx(0.3 * ALPHA * max_i + 0.3 * max_i + 0.4 * TH[0])
    assert th[2] == pytest.approx(0.3 * BETA * min_i + 0.3 * min_i + 0.4 * TH[3])
    assert hist[0][0] == 1


def test_jump_equals_loop_on_random_signals():
    rng = np.random.default_rng(1)
    for _ in range(20):
        t = np.arange(4000) / 100
        a = 9.8 + rng.uniform(0.5, 4) * np.sin(2 * np.pi * rng.uniform(1.0, 2.5) * t) + rng.normal(0, rng.uniform(0.05, 1.0), len(t))
        a[rng.integers(0, 4000, 5)] = 10.3  # exact threshold values
        for kw in (
            dict(max_step_samples=200, end_timeout_samples=30),
            dict(max_step_samples=int(rng.integers(5, 60)), end_timeout_samples=int(rng.integers(1, 10))),
        ):
            e1, _, _ = selflearn_fsm_run(a, TH, jump=True, **kw)
            e2, _, _ = selflearn_fsm_run(a, TH, jump=False, **kw)
            np.testing.assert_array_equal(e1, e2)


def test_real_data_and_segments(ifsm_recs):
    for rec, n_true in zip(ifsm_recs, (284, 319), strict=True):
        det = SelfLearningFSMStepDetector().detect(rec)
        n = len(det.steps_)
        assert 1 - abs(n - n_true) / n_true >= 0.98
        seg = det.segments_
        assert len(seg) == n and (seg["end"] > seg["start"]).all()
        st = det.steps_
        assert (st["start"] <= seg["start"]).all() and (seg["end"] == st["end"]).all()
        assert (st["peak"] >= st["s2"]).all() and (st["peak"] < st["s4"]).all()
        assert det.thresholds_["thr_peak_ms2"] != 10.4 and len(det.learning_) == 15


def test_bad_params(ifsm_recs):
    from gaitml.errors import InputError

    with pytest.raises(InputError, match="alpha"):
        SelfLearningFSMStepDetector(alpha=1.5).detect(ifsm_recs[0])
