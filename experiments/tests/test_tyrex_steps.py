"""The tyrex step reference (experiments/scripts/tyrex_steps.py) on synthetic motion capture with a known step count."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.tyrex_steps import mocap_steps
from experiments.tests.mocap_fakes import circle_walk, fake_truth


@pytest.mark.parametrize("motion", ["FrontPocket", "Swinging", "RunningPocket"])
@pytest.mark.parametrize("stride_hz", [0.55, 0.9, 1.45])
def test_limb_rule_counts_two_steps_per_swing(motion, stride_hz):
    t, pos, rot, strides = circle_walk(stride_hz=stride_hz)
    ref = mocap_steps(fake_truth(t, pos, rot), motion)
    assert abs(ref["n_steps"] - 2 * strides) <= 4  # the first and last half stride may be cut by the filter edges


@pytest.mark.parametrize("stride_hz", [0.5, 0.9])
def test_trunk_rule_counts_one_step_per_bounce(stride_hz):
    t, pos, rot, strides = circle_walk(stride_hz=stride_hz, swing_deg=0.0, bounce_cm=1.0)
    ref = mocap_steps(fake_truth(t, pos, rot), "Texting")
    assert abs(ref["n_steps"] - 2 * strides) <= 3


@pytest.mark.parametrize("motion", ["Phoning", "BackPocket"])
def test_no_steps_while_standing(motion):
    """Swinging and bouncing stop while the walker stands: nothing is counted there (a standing phone only sways)."""
    t, pos, rot, strides = circle_walk(standing=(20.0, 40.0))
    stand = (t >= 20.0) & (t < 40.0)
    sway = 0.002 * np.sin(2 * np.pi * 1.7 * t)  # 2 mm of sway at a step's rhythm
    pos[stand, 2] += sway[stand]
    ref = mocap_steps(fake_truth(t, pos, rot), motion)
    inside = (ref["t_s"] > 22.0) & (ref["t_s"] < 38.0)
    assert not inside.any()
    assert ref["n_steps"] >= 2 * strides - 6
