"""The tyrex realism statistics (experiments/scripts/realism_tyrex.py) on signals whose answers are known."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts.realism_tyrex import FIT_GRID, carried_statistics, patched_ranges


def _rocking_phone(fs=50.0, seconds=30.0, cadence=1.8, swing_deg=12.0, vert_ms2=2.0):
    """A phone rocking about its x axis (horizontal) at half the cadence, bouncing at the cadence."""
    t = np.arange(0, seconds, 1 / fs)
    a = np.radians(swing_deg) * np.sin(np.pi * cadence * t)
    rate = np.radians(swing_deg) * np.pi * cadence * np.cos(np.pi * cadence * t)
    up = np.column_stack([0 * t, np.sin(a), np.cos(a)])  # the room's up in the phone's axes
    f_up = 9.81 + vert_ms2 * np.cos(2 * np.pi * cadence * t)
    acc = up * f_up[:, None]
    gyr = np.column_stack([rate, 0 * t, 0 * t])
    return acc, gyr, up, fs


def test_known_cadence_rate_and_swing():
    acc, gyr, up, fs = _rocking_phone()
    s = carried_statistics(acc, gyr, up, fs, np.ones(len(acc), bool))
    assert s["cadence_hz"] == pytest.approx(1.8, abs=0.07)
    expect_rms = np.radians(12.0) * np.pi * 1.8 / np.sqrt(2)
    assert s["gyr_horiz"] == pytest.approx(expect_rms, rel=0.1)
    assert s["gyr_vert"] < 0.1 * expect_rms
    # the 2 s mean spans 1.8 cycles here, so it wobbles a little: the swing reads 10-14 deg
    assert 10.0 <= s["tilt_swing_deg"] <= 14.0
    assert s["gyr_pow_stride"] > 0.8 and s["gyr_pow_step"] < 0.1
    assert s["acc_pow_step"] > 0.8


def test_only_moving_stretches_count():
    acc, gyr, up, fs = _rocking_phone()
    mask = np.zeros(len(acc), bool)
    assert carried_statistics(acc, gyr, up, fs, mask) == {}
    mask[: int(3 * fs)] = True  # shorter than the shortest stretch used
    assert carried_statistics(acc, gyr, up, fs, mask) == {}
    mask[:] = False
    mask[100:900] = True
    assert carried_statistics(acc, gyr, up, fs, mask)["moving_s"] == pytest.approx(16.0)


def test_patching_restores_the_simulator():
    import gaitml.simulate.positions as pos_mod

    arm, turn, band = pos_mod.ARM_SWING_DEG_RANGE, pos_mod.POCKET_TURN_DEG_RANGE, pos_mod.POCKET_TURN_BAND_HZ
    for pos, grid in FIT_GRID.items():
        with patched_ranges(pos, grid[-1]):
            assert (pos_mod.ARM_SWING_DEG_RANGE, pos_mod.POCKET_TURN_DEG_RANGE, pos_mod.POCKET_TURN_BAND_HZ) != (arm, turn, band)
    assert (pos_mod.ARM_SWING_DEG_RANGE, pos_mod.POCKET_TURN_DEG_RANGE, pos_mod.POCKET_TURN_BAND_HZ) == (arm, turn, band)
