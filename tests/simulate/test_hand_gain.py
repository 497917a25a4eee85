"""The hand gain of a hand-held phone (gaitml.simulate.subject): what it damps, what it leaves alone, its draw."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate import simulate_dataset
from gaitml.simulate.subject import HAND_GAIN_RANGE, HAND_TILTED_PITCH_DEG, Subject, sample_subjects


def _walks(gains, modes=("walk",), positions=None, duration_s=30.0):
    """The same subject and seed at each gain (one call each: a recording's random stream depends on its index)."""
    subs = [dataclasses.replace(Subject(), hand_gain=g) for g in gains]
    return [simulate_dataset(1, duration_s, modes, seed=3, subjects=[s], positions=positions)[0] for s in subs]


def test_hand_gain_damps_walking_at_the_hand_in_every_axis():
    full, calm = _walks([1.0, 0.4])
    a, b = full.acc, calm.acc
    g = np.median(np.linalg.norm(a, axis=1))
    assert np.std(np.linalg.norm(b, axis=1)) < 0.55 * np.std(np.linalg.norm(a, axis=1))
    # every axis moves less (gravity is a constant per axis here: compare the spread, not the mean)
    assert np.all(b.std(axis=0) < a.std(axis=0))
    assert abs(np.median(np.linalg.norm(b, axis=1)) - g) < 0.3  # gravity itself is not damped
    # same steps, same ground truth
    assert np.array_equal(full.reference["steps_t_s"], calm.reference["steps_t_s"])


def test_running_and_carried_phones_ignore_the_hand_gain():
    run_full, run_calm = _walks([1.0, 0.4], modes=("run",))
    assert np.array_equal(run_full.acc, run_calm.acc)
    for pos in ("front-pocket", "bag"):
        full, calm = _walks([1.0, 0.4], positions=(pos,), duration_s=20.0)
        assert np.array_equal(full.acc, calm.acc), pos


def test_default_subject_has_gain_one_and_drawn_gains_stay_in_range():
    assert Subject().hand_gain == 1.0
    gains = np.array([s.hand_gain for s in sample_subjects(200, 5)])
    lo, hi = HAND_GAIN_RANGE
    assert gains.min() >= lo and gains.max() <= hi
    # log-uniform: about half the subjects below the geometric middle
    assert 0.4 < np.mean(gains < np.sqrt(lo * hi)) < 0.6


#: Subject S01 of seed 9 (flat) as drawn before the tilted pitch range was fitted.
FLAT_S01_PITCH = 0.12210360697185185


def test_the_gain_is_drawn_last_so_other_parameters_keep_their_seeded_values():
    """Subject S02 of seed 9 as drawn before the hand gain existed (gaitml at 465f11e: the same
    dict for all three subjects, checked when the gain was added); the first and the last
    parameter drawn before the gain are pinned. Its pose is tilted: the pitch is the same
    uniform draw, mapped since onto the fitted tilted range (0.65581 rad of 0.52-0.87 then)."""
    s = sample_subjects(3, 9)[1].to_dict()
    pinned = {"walk_cadence_hz": 2.051129, "walk_vertical_ms2": 3.459382, "hand_jitter_drift": 0.325248}
    assert {k: s[k] for k in pinned} == pinned
    lo, hi = np.radians(HAND_TILTED_PITCH_DEG)
    assert s["pose"] == "tilted"
    # a flat subject is drawn as before the tilted range was fitted (its pitch as gaitml at 6c8d3b0 drew it)
    flat = [x for x in sample_subjects(3, 9) if x.pose == "flat"]
    assert flat and flat[0].subject == "S01" and flat[0].pitch_rad == pytest.approx(FLAT_S01_PITCH, abs=1e-12)
    assert (s["pitch_rad"] - lo) / (hi - lo) == pytest.approx((0.65581 - 0.52) / (0.87 - 0.52), abs=2e-5)


@pytest.mark.parametrize("bad", [0.0, -1.0, 3.0])
def test_hand_gain_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="hand_gain"):
        Subject(hand_gain=bad)
