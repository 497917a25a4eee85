"""The phone: how it is held, how it turns, and what its IMU measures.

Frames: navigation frame x = east, y = north, z = up; phone frame x right,
y forward (towards the top of the screen), z out of the screen (up when the
phone lies flat). The phone attitude is ``R = Rz(alpha) Rx(pitch) Ry(roll)``
(phone -> navigation), with the yaw ``alpha = -theta`` because the compass
heading ``theta`` turns clockwise while a right-handed rotation about up is
counter-clockwise. So when the phone is flat and the person turns right
(``theta`` increasing), the gyroscope's z axis reads a *negative* rate.
Positive pitch raises the top of the phone (gravity then appears on +y:
``f_y = g sin(pitch)``, as in the real flat-held files, mean acc_y about
1.4 m/s^2, i.e. 8 deg).

The accelerometer measures the specific force ``f = R^T (a + g z_up)`` and
the gyroscope the body angular rate ``omega = R^T R'`` (vee), both computed
from the same angles, so gravity in the phone frame and the gyro agree. For
this Euler sequence ``omega = Ry^T Rx^T (0, 0, alpha') + Ry^T (pitch', 0, 0)
+ (0, roll', 0)``.

On top of the rigid-body motion the hand vibrates while the person moves:
band-limited (3-15 Hz) noise on all accelerometer axes (``hand_jitter_ms2``,
about 0.2-0.6 m/s^2: the real flat-held walks have 0.45-0.5 m/s^2 of
horizontal content above the N = 5 moving average) and a smaller part on the
gyroscope; a little of it (15 %) remains while standing (tremor).
"""

from __future__ import annotations

import numpy as np
import scipy.signal

from gaitml.consts import GRAVITY_MS2

__all__ = ["smooth_noise", "band_noise", "nav_to_phone", "body_rates", "specific_force", "ACC_RESOLUTION_MS2", "GYR_RESOLUTION_RADS"]

#: Output resolution of the simulated sensor (values are rounded to it): finer
#: than a phone accelerometer's LSB (about 0.002-0.005 m/s^2), and it keeps
#: the written CSV files compact.
ACC_RESOLUTION_MS2 = 1e-4
GYR_RESOLUTION_RADS = 1e-5


def smooth_noise(rng: np.random.Generator, n: int, fs_hz: float, correlation_time_s: float, n_channels: int = 1) -> np.ndarray:
    """Zero-mean, unit-std, smooth random signals (n, n_channels).

    White noise through a zero-phase 2nd-order Butterworth low-pass at
    ``1 / correlation_time_s`` Hz: a slow wander whose derivative (the gyro
    part) is smooth too.
    """
    pad = int(3 * correlation_time_s * fs_hz) + 16
    x = rng.standard_normal((n + 2 * pad, n_channels))
    fc = min(1.0 / correlation_time_s, 0.45 * fs_hz)
    sos = scipy.signal.butter(2, fc, fs=fs_hz, output="sos")
    y = scipy.signal.sosfiltfilt(sos, x, axis=0)[pad : pad + n]
    sd = y.std(axis=0)
    return (y - y.mean(axis=0)) / np.where(sd > 0, sd, 1.0)


def band_noise(rng: np.random.Generator, n: int, fs_hz: float, low_hz: float, high_hz: float, n_channels: int = 1) -> np.ndarray:
    """Zero-mean, unit-std band-limited noise (n, n_channels): white noise through a
    zero-phase 2nd-order Butterworth band-pass ``[low_hz, min(high_hz, 0.45 fs)]``."""
    pad = int(2 * fs_hz / low_hz) + 16
    x = rng.standard_normal((n + 2 * pad, n_channels))
    sos = scipy.signal.butter(2, [low_hz, min(high_hz, 0.45 * fs_hz)], btype="bandpass", fs=fs_hz, output="sos")
    y = scipy.signal.sosfiltfilt(sos, x, axis=0)[pad : pad + n]
    sd = y.std(axis=0)
    return (y - y.mean(axis=0)) / np.where(sd > 0, sd, 1.0)


def nav_to_phone(v: np.ndarray, yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """Rotate navigation-frame vectors (n, 3) into the phone frame: ``R^T v``."""
    ca, sa = np.cos(yaw), np.sin(yaw)
    x = ca * v[:, 0] + sa * v[:, 1]
    y = -sa * v[:, 0] + ca * v[:, 1]
    z = v[:, 2]
    cp, sp = np.cos(pitch), np.sin(pitch)
    y, z = cp * y + sp * z, -sp * y + cp * z
    cr, sr = np.cos(roll), np.sin(roll)
    x, z = cr * x - sr * z, sr * x + cr * z
    return np.column_stack([x, y, z])


def body_rates(yaw_rate, pitch, pitch_rate, roll, roll_rate) -> np.ndarray:
    """Phone-frame angular rate (n, 3) in rad/s for ``R = Rz(yaw) Rx(pitch) Ry(roll)``."""
    sp, cp = np.sin(pitch), np.cos(pitch)
    vx, vy, vz = pitch_rate, sp * yaw_rate, cp * yaw_rate
    cr, sr = np.cos(roll), np.sin(roll)
    return np.column_stack([cr * vx - sr * vz, vy + roll_rate, sr * vx + cr * vz])


def specific_force(acc_nav: np.ndarray, yaw, pitch, roll) -> np.ndarray:
    """Phone-frame specific force: the body acceleration plus the reaction to gravity."""
    f = acc_nav.copy()
    f[:, 2] += GRAVITY_MS2
    return nav_to_phone(f, yaw, pitch, roll)
