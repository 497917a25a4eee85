"""Fixtures of the step tests: the real recordings, read once per session."""

import numpy as np
import pytest

from gaitml.recording import Recording
from tests.conftest import shared


@pytest.fixture(scope="session")
def ifsm_recs():
    """The two IFSM flat-held phone recordings (paper 000), skipped when absent."""
    from gaitml.io import read_recording

    return [read_recording(shared("ifsm-flat-phone", f"acceleration_flat_holding_{i}.xlsx")) for i in (1, 2)]


def synthetic_walk(n_steps=20, step_period_s=0.55, fs=50.0, amp_ms2=3.0, lead_s=2.0, noise_ms2=0.05, seed=0):
    """A flat-held walk: gravity along z plus one sinusoidal step cycle per step, still lead-in / lead-out."""
    rng = np.random.default_rng(seed)
    n_lead = int(lead_s * fs)
    n_walk = int(round(n_steps * step_period_s * fs))
    t = np.arange(n_walk) / fs
    walk = amp_ms2 * np.sin(2 * np.pi * t / step_period_s)
    z = np.concatenate([np.zeros(n_lead), walk, np.zeros(n_lead)]) + 9.80665
    n = len(z)
    acc = np.column_stack([rng.normal(0, noise_ms2, n), rng.normal(0, noise_ms2, n), z + rng.normal(0, noise_ms2, n)])
    true_peaks_s = lead_s + (np.arange(n_steps) + 0.25) * step_period_s
    return Recording.from_arrays(acc, fs, reference={"steps_t_s": true_peaks_s, "n_steps_true": n_steps})
