"""The diagnosis helpers of experiments/scripts/tyrex_steps_misses.py on synthetic motion capture."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.tyrex_steps_misses import body_state, reference_check
from experiments.tests.mocap_fakes import circle_walk, fake_truth


def test_body_state_speed_and_turn_rate_on_a_circle():
    """1 m/s round a 2 m circle: speed 1 m/s, the direction of travel turns at 1/2 rad/s (28.6 deg/s)."""
    t, pos, rot, _ = circle_walk(speed=1.0)
    _, speed, turn = body_state(fake_truth(t, pos, rot))
    mid = (t > 10) & (t < 50)
    assert np.median(speed[mid]) == pytest.approx(1.0, rel=0.05)
    assert np.median(turn[mid]) == pytest.approx(np.degrees(0.5), rel=0.1)


def test_reference_check_consistent_when_the_bounce_is_once_per_step():
    t, pos, rot, _ = circle_walk(stride_hz=0.8, bounce_cm=1.0)
    c = reference_check(fake_truth(t, pos, rot), "Texting")
    assert c["consistent"] >= 0.9 * sum(c.values()) > 0


def test_reference_check_flags_a_reference_that_counts_strides():
    """A bounce once per stride (the trunk reference would count half the steps) is flagged, not passed."""
    t, pos, rot, _ = circle_walk(stride_hz=0.8, bounce_cm=1.0)
    phase = 0.8 * t
    pos[:, 2] = 1.0 + 0.01 * np.cos(2 * np.pi * phase)
    c = reference_check(fake_truth(t, pos, rot), "Texting")
    assert c["stride"] >= 0.9 * sum(c.values()) > 0
