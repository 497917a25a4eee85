"""phyphox exports (folder, zip, single table), built from the documented table layout."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.io import detect_format, read_phyphox, read_recording
from tests.io_apps._make import PHY_ACC, acc_true, gyr_true, measured, phyphox_export, write_csv, zip_folder


def _grid_true(rec):
    return rec.meta["t0_original_s"] + rec.t_s


def _check_values(rec, tol_acc=0.02, tol_gyr=0.005):
    t = _grid_true(rec)
    # linear interpolation of 0.5-2 Hz signals logged at ~100 Hz: error << 1 %
    assert np.max(np.abs(rec.acc - acc_true(t))) < tol_acc
    if rec.has_gyr:
        m = measured(rec)  # where the gyroscope ran (the clock merge holds its edge samples elsewhere)
        assert np.max(np.abs(rec.gyr[m] - gyr_true(t[m]))) < tol_gyr


def test_folder_export_with_gyroscope_merges_clocks(tmp_path):
    d = phyphox_export(tmp_path / "walk")
    assert detect_format(d) == "phyphox"
    rec = read_recording(d)
    assert rec.meta["format"] == "phyphox" and rec.has_gyr
    assert rec.sampling_rate_hz == pytest.approx(100.0, rel=0.01)
    merge = rec.meta["clock_merge"]
    # the gyroscope starts 0.05 s late and stops 0.1 s early: every accelerometer sample is kept,
    # the gyroscope's missing ends are reported (and warned about: more than a few samples)
    lo, hi = merge["overlap_s"]
    assert lo >= 0.05 and hi <= 19.9 + 1e-9
    assert rec.meta["t0_original_s"] < 0.05
    assert rec.meta["t0_original_s"] + rec.duration_s > 19.9
    assert merge["acc_rate_hz"] == pytest.approx(100, rel=0.02) and merge["gyr_rate_hz"] == pytest.approx(200, rel=0.02)
    assert merge["dropped_acc_samples"] == 0 and merge["filled_gyr_samples"] > 0 and len(merge["gyr_filled_s"]) == 2
    assert any("filled" in w for w in rec.meta["warnings"])
    _check_values(rec)
    assert np.median(rec.acc[:, 2]) == pytest.approx(9.80665, abs=0.1)  # gravity kept, m/s^2


def test_zip_export_same_as_folder(tmp_path):
    d = phyphox_export(tmp_path / "walk")
    z = zip_folder(d, tmp_path / "walk 2023-11-14.zip", root="walk 2023-11-14")
    assert detect_format(z) == "phyphox"
    a, b = read_recording(d), read_recording(z)
    np.testing.assert_array_equal(a.acc, b.acc)
    np.testing.assert_array_equal(a.gyr, b.gyr)
    assert b.meta["source"] == str(z)


def test_single_table_semicolon_decimal_comma(tmp_path):
    d = phyphox_export(tmp_path / "x", gyro=False, sep=";", decimal=",")
    f = d / "Accelerometer.csv"
    assert detect_format(f) == "phyphox"
    rec = read_phyphox(f)
    assert not rec.has_gyr and "clock_merge" not in rec.meta
    _check_values(rec)


def test_single_table_with_two_time_columns(tmp_path):
    t_a = np.arange(0, 10, 0.01)
    t_g = np.arange(0.003, 9.0, 0.005)
    a, g = acc_true(t_a), gyr_true(t_g)
    n = len(t_g)
    pad = lambda x: np.concatenate([x, np.full(n - len(x), np.nan)])  # noqa: E731
    header = PHY_ACC[:4] + ["Time (s)", "Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)"]
    write_csv(tmp_path / "Raw Data.csv", header, [pad(t_a), *(pad(c) for c in a.T), t_g, *g.T], fmt="{:.9g}")
    text = (tmp_path / "Raw Data.csv").read_text().replace("nan", "")
    (tmp_path / "Raw Data.csv").write_text(text)
    rec = read_recording(tmp_path / "Raw Data.csv")
    assert rec.has_gyr and rec.meta["clock_merge"]["overlap_s"][1] <= 9.0
    _check_values(rec)


def test_linear_acceleration_only_is_refused(tmp_path):
    d = phyphox_export(tmp_path / "lin", linear_only=True, gyro=False)
    with pytest.raises(InputError, match="Acceleration with g") as exc:
        read_recording(d)
    assert "\n" not in str(exc.value)


def test_gyroscope_only_is_refused(tmp_path):
    d = phyphox_export(tmp_path / "g")
    (d / "Accelerometer.csv").unlink()
    with pytest.raises(InputError, match="no accelerometer table"):
        read_phyphox(d)


def test_empty_table_is_refused(tmp_path):
    d = phyphox_export(tmp_path / "e")
    (d / "Gyroscope.csv").write_text('"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"\n')
    with pytest.raises(InputError, match="no samples"):
        read_phyphox(d)


def test_zero_byte_accelerometer_table_is_named(tmp_path):
    d = phyphox_export(tmp_path / "z")
    (d / "Accelerometer.csv").write_bytes(b"")
    with pytest.raises(InputError, match="Accelerometer.csv of z is empty"):
        read_recording(d)


def test_clocks_without_overlap_are_refused(tmp_path):
    d = phyphox_export(tmp_path / "o", gyr_offset_s=30.0, gyr_end_s=50.0, duration_s=20.0)
    with pytest.raises(InputError, match="do not overlap"):
        read_phyphox(d)


def test_unsynchronised_clocks_are_refused(tmp_path):
    d = phyphox_export(tmp_path / "u", gyr_offset_s=15.0, gyr_end_s=45.0, duration_s=30.0)
    with pytest.raises(InputError, match="unsynchronised"):
        read_phyphox(d)


def test_folder_of_separate_tables_is_a_dataset(tmp_path):
    for i in range(2):
        d = phyphox_export(tmp_path / f"tmp{i}", gyro=False)
        (d / "Accelerometer.csv").rename(tmp_path / f"walk{i}.csv")
    for i in range(2):
        import shutil

        shutil.rmtree(tmp_path / f"tmp{i}")
    assert detect_format(tmp_path) == "mixed-folder"
    from gaitml.io import read_dataset

    recs = read_dataset(tmp_path)
    assert [r.meta["format"] for r in recs] == ["phyphox", "phyphox"]
