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


def held_out_phone(seconds=40.0, *, walk_speed=0.0, turn_rads=1.0, lever_m=0.4, bounce_cm=0.0, step_hz=1.8, radius_m=2.0):
    """A phone held in front at ``lever_m`` of a person who turns on the spot (``walk_speed`` 0) or walks a circle.

    The phone's +z axis points where the person faces (the AR pose of the motion capture); its
    height bobs ``bounce_cm`` peak-to-peak at ``step_hz``. Turning on the spot, the person faces
    ``turn_rads * t``; walking, the person goes round a circle of ``radius_m`` facing along it.
    """
    t = np.arange(0, seconds, 1 / FS)
    if walk_speed > 0:
        ang = walk_speed * t / radius_m
        body = np.column_stack([radius_m * np.cos(ang), radius_m * np.sin(ang)])
        heading = ang + np.pi / 2
    else:
        body = np.zeros((len(t), 2))
        heading = turn_rads * t
    fwd = np.column_stack([np.cos(heading), np.sin(heading)])
    z = 1.4 + 0.005 * bounce_cm * np.cos(2 * np.pi * step_hz * t)
    pos = np.column_stack([body + lever_m * fwd, z])
    # phone axes in the room: z forward (horizontal), x down (landscape), y = z cross x
    ez = np.column_stack([fwd, np.zeros(len(t))])
    ex = np.tile([0.0, 0.0, -1.0], (len(t), 1))
    ey = np.cross(ez, ex)
    rot = np.stack([ex, ey, ez], axis=2)  # columns: the phone's axes in room coordinates
    return t, pos, rot
