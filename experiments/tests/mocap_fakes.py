"""Synthetic motion capture for the lab's tyrex tests: a walker on a circle with a known step count."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from scipy.spatial.transform import Rotation

FS = 60.0


def fake_truth(t, pos, rot):
    return SimpleNamespace(t_s=t, pos_m=pos, rot=rot, frame_rate_hz=FS, valid=np.isfinite(pos).all(axis=1))


def circle_walk(seconds=60.0, stride_hz=0.9, speed=1.0, swing_deg=20.0, bounce_cm=2.0, standing=(0.0, 0.0)):
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
