"""Gravity direction and tilt from the accelerometer."""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError
from gaitml.signal._basic import lowpass, magnitude

__all__ = ["gravity_direction", "tilt_angles", "gravity_components"]


def gravity_direction(acc: np.ndarray, sampling_rate_hz: float | None = None, *, cutoff_hz: float = 0.3) -> np.ndarray:
    """Unit gravity ("up", since a resting accelerometer reads +g upward) in the sensor frame.

    Without ``sampling_rate_hz``: one direction, the normalised mean of ``acc``
    (for a phone held still or in a steady pose) -> shape (3,). With it: a
    per-sample direction from a zero-phase low-pass at ``cutoff_hz`` -> shape (n, 3).
    """
    a = np.asarray(acc, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise InputError(f"`acc` must have shape (n, 3), got {a.shape}.")
    if sampling_rate_hz is None:
        m = a.mean(axis=0)
        norm = np.linalg.norm(m)
        if norm == 0:
            raise InputError("the mean acceleration is zero, so gravity has no direction; check the data includes gravity.")
        return m / norm
    g = lowpass(a, cutoff_hz, sampling_rate_hz, order=2)
    n = magnitude(g)[:, None]
    n[n == 0] = 1.0
    return g / n


def tilt_angles(gravity_up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roll and pitch (rad) of the sensor from its up direction (x right, y forward, z up when flat).

    roll = atan2(g_x... ) conventions: pitch is the rotation about x that lifts
    the y axis, roll the rotation about y; a flat phone (up = +z) has both 0.
    """
    g = np.asarray(gravity_up, dtype=float)
    gx, gy, gz = g[..., 0], g[..., 1], g[..., 2]
    pitch = np.arctan2(gy, np.sqrt(gx**2 + gz**2))
    roll = np.arctan2(-gx, gz)
    return roll, pitch


def gravity_components(acc: np.ndarray, gravity_up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split specific force into the vertical component (along up, m/s^2) and the horizontal vector.

    Returns ``(vertical (n,), horizontal (n, 3))``; ``vertical`` includes gravity
    (about +9.8 at rest), ``horizontal`` is orthogonal to ``gravity_up``.
    """
    a = np.asarray(acc, dtype=float)
    u = np.asarray(gravity_up, dtype=float)
    if u.ndim == 1:
        u = np.broadcast_to(u, a.shape)
    v = np.einsum("ij,ij->i", a, u)
    return v, a - v[:, None] * u
