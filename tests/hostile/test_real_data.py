"""Every real recording in ../shared/data is is accepted by the input checks.

The gap limit, the sensor-range limits and the gyro-unit judgement must refuse
hostile files, never a real one: each recording is read, has no gap too long to
bridge, stays inside the sensor ranges with a margin, and raises no unit warning.
"""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.consts import ACC_LIMIT_MS2, GYR_LIMIT_RADS
from gaitml.io import list_dataset, read_recording
from gaitml.recording import max_bridge_s
from tests.conftest import shared

pytestmark = pytest.mark.realdata

FOLDERS = ("ifsm-flat-phone", "oxford-step-counter/optimisation", "gaitmap-example")


def _recordings():
    out = []
    for folder in FOLDERS:
        for path, fmt in list_dataset(shared(folder)):
            out.append((path, fmt))
    return out


def test_every_real_recording_is_accepted():
    found = _recordings()
    assert len(found) >= 2 + 48 + 7  # at least IFSM, Oxford, gaitmap IMU files (the tables are not recordings)
    for path, fmt in found:
        rec = read_recording(path, format=fmt)
        assert rec.n_samples > 1000, path
        assert not rec.meta.get("warnings"), (path, rec.meta.get("warnings"))
        # well inside the limits: the limits are not tuned to the data
        assert np.abs(rec.acc).max() < ACC_LIMIT_MS2 / 10, path
        if rec.gyr is not None:
            assert np.abs(rec.gyr).max() < GYR_LIMIT_RADS / 10, path
        if "max_interval_s" in rec.meta:
            assert rec.meta["max_interval_s"] < max_bridge_s(1 / rec.meta["original_rate_hz"]) / 10, path
    if any(fmt == "gaitmap" for _, fmt in found):
        for sensor in ("left", "right"):
            assert read_recording(shared("gaitmap-example", "imu_sample.csv.gz"), sensor=sensor).has_gyr
