"""Resampling keeps a recording on its own clock (the truth of a tyrex recording is aligned by it)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.models import resample_recording
from gaitml.recording import Recording


@pytest.mark.parametrize("fs", [50.0, 20.0, 400.0])
def test_resampling_keeps_the_first_sample_time_on_the_recording_clock(fs):
    t = 0.6 + np.arange(0, 30, 1 / 199.0)
    acc = np.column_stack([np.sin(t), np.cos(t), 9.8 + np.sin(3 * t)])
    rec = Recording.from_timestamps(t, acc, gyr=0.1 * acc)
    assert rec.meta["t0_original_s"] == pytest.approx(0.6)
    low = resample_recording(rec, fs)
    assert low.meta["t0_original_s"] == pytest.approx(0.6, abs=1e-9)
    # an event at a time on the recording's clock is found at the same time after resampling
    t_evt = 12.3456
    k = int(np.argmin(np.abs(low.meta["t0_original_s"] + low.t_s - t_evt)))
    assert abs(low.meta["t0_original_s"] + low.t_s[k] - t_evt) <= 0.5 / fs
    np.testing.assert_allclose(low.acc[k, 2], 9.8 + np.sin(3 * (low.meta["t0_original_s"] + low.t_s[k])), atol=0.02)
    # twice: still the same clock
    assert resample_recording(low, 100.0).meta["t0_original_s"] == pytest.approx(0.6, abs=1e-9)
