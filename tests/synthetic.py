"""Synthetic recordings shared by the tests and the benchmarks (not part of the package)."""

from __future__ import annotations

import numpy as np

from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording

__all__ = ["synthetic_foot_walk"]


def synthetic_foot_walk(n_samples: int, sampling_rate_hz: float = 100.0, seed: int = 0) -> Recording:
    """A foot-mounted-like recording: stance (still) 40 % of each 1 s stride, swing 60 %.

    Parameters
    ----------
    n_samples : int
        Length of the recording (samples).
    sampling_rate_hz : float
        Sampling rate (Hz).
    seed : int
        Seed of the sensor noise (0.05 m/s^2 on acc, 0.01 rad/s on gyr).

    Returns
    -------
    Recording
        acc (m/s^2) and gyr (rad/s); swing phases with large rotation and acceleration.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(n_samples) / sampling_rate_hz
    phase = t % 1.0
    swing = phase >= 0.4
    env = np.where(swing, np.sin(np.pi * (phase - 0.4) / 0.6) ** 2, 0.0)
    gyr = np.column_stack([2.0 * env, 5.0 * env * np.sin(2 * np.pi * (phase - 0.4) / 0.6), 0.5 * env])
    acc = np.column_stack([8.0 * env * np.cos(2 * np.pi * phase), 2.0 * env, GRAVITY_MS2 + 6.0 * env * np.sin(4 * np.pi * phase)])
    acc += rng.normal(0, 0.05, acc.shape)
    gyr += rng.normal(0, 0.01, gyr.shape)
    return Recording(acc=acc, gyr=gyr, sampling_rate_hz=sampling_rate_hz, meta={"id": "synthetic-foot"}, check_units=False)
