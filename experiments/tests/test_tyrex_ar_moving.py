"""The walking rule on synthetic motion capture: walking passes, turning on the spot with the phone held out does not."""

from __future__ import annotations

import numpy as np

from experiments.scripts.tyrex_ar_moving import FORWARD_AXIS, NOT_WALKING, mocap_signals, walking_labels
from experiments.tests.mocap_fakes import circle_walk, held_out_phone
from gaitml.evaluation.trajectory import MOVING_SPEED_MS

AR = FORWARD_AXIS["AR"]


def _share(lab, what, t, lo=5.0, hi=None):
    m = (t > lo) & (t < (t[-1] - 5.0 if hi is None else hi))
    return float(np.mean(lab[m] == what))


def test_turning_on_the_spot_with_the_phone_held_out_is_moving_by_speed_but_not_walking():
    """1 rad/s at 0.4 m: the phone sweeps 0.4 m/s (over the speed rule's 0.3), the body point stands and nothing bobs."""
    t, pos, rot = held_out_phone(turn_rads=1.0, lever_m=0.4)
    s = mocap_signals(t, pos, rot, lever_m=0.4, forward_axis=AR)
    mid = (t > 5) & (t < t[-1] - 5)
    assert np.median(s["speed"][mid]) > MOVING_SPEED_MS  # the speed rule calls it moving
    assert np.median(s["speed_lever"][mid]) < 0.1 * MOVING_SPEED_MS  # the corrected point is where the person stands
    assert np.median(np.abs(s["yaw_rate"][mid])) > 0.8
    assert np.median(s["radius"][mid]) < 0.6
    lab = walking_labels(t, t, pos, rot, "walk", lever_m=0.4, forward_axis=AR)
    assert _share(lab, NOT_WALKING, t) > 0.95


def test_stepping_round_on_the_spot_still_is_not_walking():
    """Turning on the spot with small steps that bob the phone: the corrected point does not travel."""
    t, pos, rot = held_out_phone(turn_rads=1.0, lever_m=0.4, bounce_cm=2.0)
    lab = walking_labels(t, t, pos, rot, "walk", lever_m=0.4, forward_axis=AR)
    assert _share(lab, "walk", t) < 0.05


def test_walking_with_the_phone_held_out_passes():
    t, pos, rot = held_out_phone(walk_speed=0.8, lever_m=0.4, bounce_cm=2.0)
    s = mocap_signals(t, pos, rot, lever_m=0.4, forward_axis=AR)
    mid = (t > 5) & (t < t[-1] - 5)
    assert np.median(s["speed_lever"][mid]) > 0.6  # body at 0.8 m/s on a 2 m circle (the phone at 2.4 m goes 0.96)
    assert np.median(s["bounce_cm"][mid]) > 1.5  # 2 cm peak-to-peak put in
    lab = walking_labels(t, t, pos, rot, "walk", lever_m=0.4, forward_axis=AR)
    assert _share(lab, "walk", t) > 0.95


def test_gliding_without_a_bounce_is_not_walking():
    """Speed alone does not make walking: the same path without the step-band bounce fails the rule."""
    t, pos, rot = held_out_phone(walk_speed=0.8, lever_m=0.4, bounce_cm=0.0)
    lab = walking_labels(t, t, pos, rot, "walk", lever_m=0.4, forward_axis=AR)
    assert _share(lab, "walk", t) < 0.05


def test_the_circle_walker_walks_and_its_standing_is_still():
    """The lab's circle walker (1 m/s, 2 cm bounce per step) with a 10 s stop: walking, then still, then walking."""
    t, pos, rot, _ = circle_walk(seconds=50.0, standing=(20.0, 30.0))
    lab = walking_labels(t, t, pos, rot, "walk", lever_m=0.0)
    assert _share(lab, "walk", t, 3.0, 17.0) > 0.95
    assert _share(lab, "still", t, 23.0, 27.0) > 0.95
    assert _share(lab, "walk", t, 33.0, 47.0) > 0.95
    assert set(walking_labels(np.array([-1.0, 60.0]), t, pos, rot, "walk", lever_m=0.0)) == {"unlabelled"}
