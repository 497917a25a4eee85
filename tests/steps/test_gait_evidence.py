"""The gait-evidence test per bout of steps (gaitml.steps._gait_evidence): a phone rotating at the step rate is no walker's."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.recording import Recording
from gaitml.simulate import Placement, Subject, simulate_recording
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import (
    LONG_BOUT_STEPS,
    MAX_STEP_ROTATION_RAD_S,
    gait_check,
    gait_check_recording,
    gait_evidence,
    rotation_amplitude,
    step_bouts,
)


def test_rotation_amplitude_recovers_a_sinusoid_under_a_drift_and_noise():
    fs, f = 50.0, 1.7
    t = np.arange(0, 3.0, 1 / fs)
    rng = np.random.default_rng(0)
    x = np.column_stack([0.8 * np.sin(2 * np.pi * f * t + 0.3), 0.6 * np.cos(2 * np.pi * f * t), np.zeros_like(t)])
    x += 0.4 + 0.2 * t[:, None] + rng.normal(0, 0.02, x.shape)
    step, stride = rotation_amplitude(x, fs, f, f / 2)
    assert step == pytest.approx(1.0, rel=0.05)
    assert stride < 0.1
    assert rotation_amplitude(x, fs, f)[0] == pytest.approx(1.0, rel=0.05)


def test_bouts_split_at_intervals_that_are_no_step_intervals():
    t = np.r_[0.0, 0.5, 1.0, 1.5, 3.5, 4.0, 4.5, 10.0]
    b = step_bouts(t, np.full(len(t), 0.5))
    assert b.tolist() == [0, 0, 0, 0, 1, 1, 1, 2]
    assert step_bouts(np.zeros(0)).size == 0


def _beating_phone(rotation_deg: float, fs: float = 50.0, beat_hz: float = 2.0, seconds: float = 30.0, bursts: bool = False):
    """A phone held still whose |acc| beats at ``beat_hz`` (2 m/s^2) while it rotates by ``rotation_deg`` at the same rate."""
    t = np.arange(0, seconds, 1 / fs)
    env = np.ones_like(t) if not bursts else (np.sin(np.pi * t / 3.0) ** 2)
    ph = 2 * np.pi * beat_hz * t
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), 9.80665 + 2.0 * env * np.sin(ph)])
    w = np.deg2rad(rotation_deg) * 2 * np.pi * beat_hz * env * np.cos(ph)
    gyr = np.column_stack([w, 0.3 * w, np.zeros_like(t)])
    rng = np.random.default_rng(1)
    return Recording.from_arrays(acc + rng.normal(0, 0.03, acc.shape), fs, gyr=gyr + rng.normal(0, 0.003, gyr.shape))


def test_a_phone_turning_at_the_step_rate_has_no_gait_evidence_and_a_still_one_has():
    # 12 s of beats at 2 Hz: a bout shorter than LONG_BOUT_STEPS, as a burst of gestures is
    turning = _beating_phone(rotation_deg=20.0, seconds=12.0)
    still = _beating_phone(rotation_deg=1.0, seconds=12.0)
    for rec, gait in ((turning, False), (still, True)):
        st = get_detector("adaptive", gait_check=False).detect(rec).steps_
        assert 15 < len(st) < LONG_BOUT_STEPS  # the acceleration alone reads as steps
        ev = gait_evidence(rec.gyr, rec.sampling_rate_hz, st)
        assert ev["tested"].all()
        assert ev["gait"].all() == gait
        if not gait:  # 20 deg at 2 Hz: 4.4 rad/s, far above the ceiling
            assert ev["rotation_step_rad_s"].min() > 3 * MAX_STEP_ROTATION_RAD_S
    assert len(get_detector("adaptive").detect(turning).steps_) == 0
    kept = get_detector("adaptive").detect(still).steps_
    assert len(kept) == len(get_detector("adaptive", gait_check=False).detect(still).steps_)
    assert kept.attrs["gait_check"]["n_steps_rejected"] == 0


def test_a_long_bout_is_gait_whatever_its_rotation():
    # 30 s of regular steps at 2 Hz (60 steps): no burst of beats lasts that long; a bag on its strap turns every step
    rec = _beating_phone(rotation_deg=20.0, seconds=30.0)
    st = get_detector("adaptive", gait_check=False).detect(rec).steps_
    assert len(st) >= LONG_BOUT_STEPS
    ev = gait_evidence(rec.gyr, rec.sampling_rate_hz, st)
    assert len(ev) == 1 and ev["long_bout"].all() and ev["gait"].all()
    assert ev["rotation_step_rad_s"].min() > 3 * MAX_STEP_ROTATION_RAD_S  # still measured and reported
    # the same bout without the exemption (a length no bout reaches) is rejected
    strict = gait_evidence(rec.gyr, rec.sampling_rate_hz, st, long_bout_steps=10**6)
    assert not strict["gait"].any()
    assert len(get_detector("adaptive").detect(rec).steps_) == len(st)


@pytest.mark.parametrize("seed", [101, 104])
def test_a_walk_with_the_phone_in_a_bag_keeps_its_steps(seed):
    # held-out seeds of experiments/reports/nongait.md (bag section): the bag pitches on its strap at every step, so
    # its rotation at the step frequency is far above the trunk's nod, yet a walk is a long bout of regular steps
    rng = np.random.default_rng(seed)
    placement = Placement.random("bag", rng)
    rec = simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=60, seed=seed, placement=placement)
    n_true = rec.reference["n_steps_true"]
    raw = get_detector("adaptive", gait_check=False).detect(rec).steps_
    ev = gait_evidence(rec.gyr, rec.sampling_rate_hz, raw)
    assert (ev["rotation_step_rad_s"] > MAX_STEP_ROTATION_RAD_S).any()  # the case the exemption is for
    on = get_detector("adaptive").detect(rec).steps_
    assert on.attrs["gait_check"]["tested"]
    assert len(on) >= 0.9 * n_true
    sp = get_detector("single-peak").detect(rec).steps_
    assert len(gait_check_recording(sp, rec)) >= 0.9 * min(len(sp), n_true)


@pytest.mark.xfail(
    strict=True,
    reason="known gap: a bag walk shorter than LONG_BOUT_STEPS (15 s, ~27 steps) rotates like a gesture burst at the "
    "step rate and loses its steps to the rotation test (experiments/reports/nongait.md, bag section)",
)
def test_a_short_walk_with_the_phone_in_a_bag_keeps_its_steps():
    rng = np.random.default_rng(0)
    placement = Placement.random("bag", rng)
    rec = simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=15, seed=0, placement=placement)
    assert len(get_detector("adaptive").detect(rec).steps_) >= 0.9 * rec.reference["n_steps_true"]


def test_without_a_gyroscope_nothing_is_tested_and_nothing_is_lost():
    rec = _beating_phone(rotation_deg=20.0)
    no_gyr = Recording.from_arrays(rec.acc, rec.sampling_rate_hz)
    st = get_detector("adaptive").detect(no_gyr).steps_
    assert len(st) == len(get_detector("adaptive", gait_check=False).detect(no_gyr).steps_) > 40
    assert st.attrs["gait_check"]["tested"] is False
    assert gait_check(st, None, rec.sampling_rate_hz).attrs["gait_check"]["n_steps_rejected"] == 0


@pytest.mark.parametrize("position", ["hand", "front-pocket", "swinging-hand", "back-pocket"])
def test_simulated_walks_keep_their_steps(position):
    # the walk's rotation is once per stride: the test must not cost a walker's steps
    for seed in (3, 4):
        rng = np.random.default_rng([seed, 9])
        placement = None if position == "hand" else Placement.random(position, rng)
        rec = simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=40, seed=seed, placement=placement)
        off = get_detector("adaptive", gait_check=False).detect(rec).steps_
        on = get_detector("adaptive").detect(rec).steps_
        assert on.attrs["gait_check"]["tested"]
        assert len(on) >= len(off) - 2


def test_gestures_lose_most_steps_on_every_detector_run_through_the_check():
    # selection seeds of the study (experiments/reports/nongait.md); truth is 0 steps
    n_off, n_on, minutes = {}, {}, 0.0
    for seed in range(4):
        rec = simulate_nongait("gestures", duration_s=120, seed=seed)
        minutes += rec.duration_s / 60
        for d in ("adaptive", "single-peak"):
            st = get_detector(d, **({"gait_check": False} if d == "adaptive" else {})).detect(rec).steps_
            n_off[d] = n_off.get(d, 0) + len(st)
            n_on[d] = n_on.get(d, 0) + len(gait_check_recording(st, rec))
    for d in n_off:
        assert n_on[d] <= 0.3 * n_off[d]
    assert n_on["adaptive"] / minutes <= 3.0


def test_gait_check_parameter_is_validated():
    from gaitml.errors import InputError

    with pytest.raises(InputError, match="gait_check"):
        get_detector("adaptive", gait_check="yes").detect(_beating_phone(1.0))


def test_cli_says_how_many_steps_were_left_out(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    path = write_gaitml_csv(_beating_phone(rotation_deg=20.0, seconds=12.0), tmp_path / "beats.csv")
    assert main(["steps", str(path), "--detector", "adfsm", "--json", "--gait-check"]) == 0
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    gc = obj["gait_check"]
    assert gc["tested"] and gc["n_steps_rejected"] > 15
    assert obj["n_steps"] == 0
    assert len(gc["rejected_t_s"]) == gc["n_steps_rejected"]
    assert cap.err.count("without gait evidence") == 1
    # off by default for the detectors other than adaptive
    assert main(["steps", str(path), "--detector", "adfsm", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["n_steps"] == gc["n_steps_rejected"]
    assert "gait_check" not in json.loads(cap.out)
    assert "without gait evidence" not in cap.err
    # on by default for adaptive, in the text summary too
    assert main(["steps", str(path), "--detector", "adaptive"]) == 0
    cap = capsys.readouterr()
    assert "gait check:" in cap.out and "without gait evidence left out" in cap.out
    assert cap.err.count("without gait evidence") == 1
    assert main(["steps", str(path), "--detector", "adaptive", "--json", "--no-gait-check"]) == 0
    assert json.loads(capsys.readouterr().out)["n_steps"] > 15


def test_a_detector_counting_strides_keeps_them_when_tested_at_adaptives_cadence():
    # one event per stride of a phone that swings with the stride (a pocket): at the detector's own rate the stride's
    # rotation sits at the "step" frequency; adaptive's cadence puts the step at twice that rate
    fs, stride_s = 50.0, 1.1
    t = np.arange(0, 25, 1 / fs)  # fewer strides than LONG_BOUT_STEPS: the rotation test applies
    ph = 2 * np.pi * t / stride_s
    acc = np.column_stack([2.0 * np.sin(ph), np.zeros_like(t), 9.80665 + 2.5 * np.cos(2 * ph) + 1.5 * np.cos(ph)])
    gyr = np.column_stack([3.0 * np.cos(ph), np.zeros_like(t), np.zeros_like(t)])
    rec = Recording.from_arrays(acc, fs, gyr=gyr)
    strides = get_detector("adaptive", gait_check=False).detect(rec).steps_.iloc[::2].reset_index(drop=True)
    assert 15 < len(strides) < LONG_BOUT_STEPS
    assert len(gait_check(strides, rec.gyr, fs)) <= 0.1 * len(strides)  # its own rate: taken for a gesture
    assert len(gait_check_recording(strides, rec)) == len(strides)
