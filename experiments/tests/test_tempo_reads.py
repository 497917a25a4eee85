"""The per-recording figures of experiments/scripts/tempo_reads.py on a synthetic run of known cadence and amplitude."""

from __future__ import annotations

import numpy as np

from experiments.scripts.tempo_reads import motion_stats
from gaitml.pipeline.augment import tempo_recording
from gaitml.recording import Recording


def test_motion_stats_reads_the_cadence_and_amplitudes_and_scale_with_a_tempo_copy():
    fs, f_stride = 50.0, 1.4  # 168 steps/min
    t = np.arange(0.0, 30.0, 1 / fs)
    gyr = np.column_stack([3.0 * np.sin(2 * np.pi * f_stride * t), 0 * t, 0 * t])
    acc = np.column_stack([0 * t, 4.0 * np.sin(2 * np.pi * 2 * f_stride * t), 9.81 + 0 * t])
    still = t < 5.0  # the runner stands first: only the run's samples count
    gyr[still] = 0.0
    acc[still, 1] = 0.0
    labels = np.where(still, "still", "run").astype(object)
    rec = Recording(acc=acc, gyr=gyr, sampling_rate_hz=fs, labels=labels, meta={"id": "syn", "position": "pocket"})
    st = motion_stats(rec, "run")
    assert abs(st["cadence"] - 168.0) <= 3.0  # one spectral bin of 25 s at 50 Hz is 4.8 steps/min
    assert abs(st["gyr_rms"] - 3.0 / np.sqrt(2)) < 0.02 and abs(st["acc_dyn_rms"] - 4.0 / np.sqrt(2)) < 0.02
    # a copy slowed to 0.87 with gravity given exactly reads 0.87 x the rate, 0.87^2 x the acceleration and cadence
    up = np.tile([0.0, 0.0, 9.81], (len(t), 1))
    slow = motion_stats(tempo_recording(rec, 0.87, up), "run")
    assert abs(slow["gyr_rms"] / st["gyr_rms"] - 0.87) < 0.02
    assert abs(slow["acc_dyn_rms"] / st["acc_dyn_rms"] - 0.87**2) < 0.03
    assert abs(slow["cadence"] - 0.87 * 168.0) <= 4.0
