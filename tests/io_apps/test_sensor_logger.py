"""Sensor Logger exports (zip, folder, one table), built from the documented units and frames."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.io import detect_format, read_recording, read_sensor_logger
from tests.io_apps._make import T0_NS, acc_true, gyr_true, measured, sensor_logger_export, zip_folder


def _true_t(rec):
    return (rec.meta["t0_epoch_ns"] - T0_NS) / 1e9 + rec.meta["t0_original_s"] + rec.t_s


def _check_values(rec):
    t = _true_t(rec)
    a = measured(rec, "gravity_merge")  # where gravity was measured (the merge holds its edge samples elsewhere)
    assert np.max(np.abs(rec.acc[a] - acc_true(t[a]))) < 0.03
    if rec.has_gyr:
        m = measured(rec)
        assert np.max(np.abs(rec.gyr[m] - gyr_true(t[m]))) < 0.005


def test_android_zip_uses_total_acceleration(tmp_path):
    d = sensor_logger_export(tmp_path / "2023-11-14_22-13-20", platform="Android")
    z = zip_folder(d, tmp_path / "2023-11-14_22-13-20.zip")
    assert detect_format(z) == "sensor-logger"
    rec = read_recording(z)
    assert rec.meta["format"] == "sensor-logger" and rec.meta["platform"] == "Android" and rec.meta["device"] == "TestPhone"
    assert rec.meta["acc_source"] == "TotalAcceleration.csv"
    assert rec.has_gyr and "clock_merge" in rec.meta
    assert rec.sampling_rate_hz == pytest.approx(100.0, rel=0.01)
    _check_values(rec)
    assert np.median(rec.acc[:, 2]) == pytest.approx(9.80665, abs=0.1)


def test_ios_folder_builds_gravity_and_flips_the_frame(tmp_path):
    d = sensor_logger_export(tmp_path / "ios", platform="iOS")
    assert not (d / "TotalAcceleration.csv").exists()
    assert detect_format(d) == "sensor-logger"
    rec = read_recording(d)
    assert rec.meta["acc_source"].startswith("Accelerometer.csv + Gravity.csv")
    assert "iOS frame negated" in rec.meta["frame"]
    _check_values(rec)  # +z up when flat, the Android convention gaitml uses


def test_one_table_reads_its_export_folder(tmp_path):
    d = sensor_logger_export(tmp_path / "a", platform="Android")
    f = d / "TotalAcceleration.csv"
    assert detect_format(f) == "sensor-logger"
    rec = read_recording(f)
    assert rec.has_gyr and rec.meta["source"] == str(d)


def test_ios_uncalibrated_in_g_is_converted(tmp_path):
    d = sensor_logger_export(tmp_path / "u", platform="iOS", gravity=False, uncalibrated=True)
    rec = read_sensor_logger(d)
    assert rec.meta["acc_source"] == "AccelerometerUncalibrated.csv" and rec.meta["converted"] == ["acc from g"]
    _check_values(rec)


def test_accelerometer_without_gravity_is_refused(tmp_path):
    d = sensor_logger_export(tmp_path / "n", platform="Android", total=False, gravity=False)
    with pytest.raises(InputError, match="without gravity.*switch on Gravity") as exc:
        read_recording(d)
    assert "\n" not in str(exc.value)


def test_gyroscope_from_another_recording_is_refused(tmp_path):
    d = sensor_logger_export(tmp_path / "s", platform="Android", gyr_shift_s=3600.0)
    with pytest.raises(InputError, match="do not overlap"):
        read_sensor_logger(d)


def test_empty_gyroscope_table_is_refused(tmp_path):
    d = sensor_logger_export(tmp_path / "e", platform="Android")
    (d / "Gyroscope.csv").write_text("time,seconds_elapsed,z,y,x\n")
    with pytest.raises(InputError, match="Gyroscope.csv.*no samples"):
        read_sensor_logger(d)


def test_without_metadata_assumes_android(tmp_path):
    d = sensor_logger_export(tmp_path / "m", platform=None)
    rec = read_sensor_logger(d, sampling_rate_hz=50.0)
    assert rec.sampling_rate_hz == 50.0 and "platform unknown" in rec.meta["frame"]
    _check_values(rec)
