"""The tyrex step reference (experiments/scripts/tyrex_steps.py) on synthetic motion capture with a known step count."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from experiments.scripts.tyrex_steps import mocap_steps

FS = 60.0


def _truth(t, pos, rot):
    return SimpleNamespace(t_s=t, pos_m=pos, rot=rot, frame_rate_hz=FS, valid=np.isfinite(pos).all(axis=1))


def _walk(seconds=60.0, stride_hz=0.9, speed=1.0, swing_deg=20.0, bounce_cm=2.0, standing=(0.0, 0.0)):
    """A walker going round a 2 m circle; the phone swings about one axis once per stride and bounces once per step."""
    t = np.arange(0, seconds, 1 / FS)
    moving = ~((t >= standing[0]) & (t < standing[1]))
    s = np.cumsum(np.where(moving, speed, 0.0)) / FS  # path length
    phase = np.cumsum(np.where(moving, stride_hz, 0.0)) / FS  # strides taken
    r = 2.0
    pos = np.column_stack([r * np.cos(s / r), r * np.sin(s / r), 1.0 + 0.005 * bounce_cm * np.cos(4 * np.pi * phase)])
    angle = np.radians(swing_deg) * np.sin(2 * np.pi * phase) * moving
    rot = Rotation.from_euler("y", angle[:, None]).as_matrix()
    return t, pos, rot, phase[-1]


@pytest.mark.parametrize("motion", ["FrontPocket", "Swinging", "RunningPocket"])
@pytest.mark.parametrize("stride_hz", [0.55, 0.9, 1.45])
def test_limb_rule_counts_two_steps_per_swing(motion, stride_hz):
    t, pos, rot, strides = _walk(stride_hz=stride_hz)
    ref = mocap_steps(_truth(t, pos, rot), motion)
    assert abs(ref["n_steps"] - 2 * strides) <= 4  # the first and last half stride may be cut by the filter edges


@pytest.mark.parametrize("stride_hz", [0.5, 0.9])
def test_trunk_rule_counts_one_step_per_bounce(stride_hz):
    t, pos, rot, strides = _walk(stride_hz=stride_hz, swing_deg=0.0, bounce_cm=1.0)
    ref = mocap_steps(_truth(t, pos, rot), "Texting")
    assert abs(ref["n_steps"] - 2 * strides) <= 3


@pytest.mark.parametrize("motion", ["Phoning", "BackPocket"])
def test_no_steps_while_standing(motion):
    """Swinging and bouncing stop while the walker stands: nothing is counted there (a standing phone only sways)."""
    t, pos, rot, strides = _walk(standing=(20.0, 40.0))
    stand = (t >= 20.0) & (t < 40.0)
    sway = 0.002 * np.sin(2 * np.pi * 1.7 * t)  # 2 mm of sway at a step's rhythm
    pos[stand, 2] += sway[stand]
    ref = mocap_steps(_truth(t, pos, rot), motion)
    inside = (ref["t_s"] > 22.0) & (ref["t_s"] < 38.0)
    assert not inside.any()
    assert ref["n_steps"] >= 2 * strides - 6
