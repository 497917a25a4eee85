"""The tyrex PDR study's own pieces: the plain baseline's steps and heading, on known-answer signals."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.tyrex_pdr import baseline_steps, gyro_heading_about_gravity
from gaitml.recording import Recording

FS = 100.0


def test_baseline_counts_the_steps_of_a_synthetic_walk():
    t = np.arange(0, 12, 1 / FS)
    cadence_hz = 1.8
    bounce = 1.5 * np.sin(2 * np.pi * cadence_hz * t) * ((t > 1) & (t < 11))
    acc = np.column_stack([0.2 * np.sin(2 * np.pi * 0.9 * t), np.zeros_like(t), 9.81 + bounce])
    rec = Recording.from_arrays(acc, FS, gyr=np.zeros_like(acc))
    n = len(baseline_steps(rec))
    assert abs(n - cadence_hz * 10) <= 1


@pytest.mark.parametrize("up_axis", [2, 1])
def test_gyro_heading_about_gravity_turns_left_by_the_integrated_rate(up_axis):
    """A left turn (counter-clockwise seen from above) of 1 rad lowers the compass heading by 1 rad, in any pose."""
    t = np.arange(0, 4, 1 / FS)
    acc = np.zeros((len(t), 3))
    acc[:, up_axis] = 9.81
    gyr = np.zeros_like(acc)
    gyr[(t >= 1) & (t < 3), up_axis] = 0.5
    rec = Recording.from_arrays(acc, FS, gyr=gyr)
    psi = gyro_heading_about_gravity(rec)
    assert psi[-1] == pytest.approx(-1.0, abs=0.01)
