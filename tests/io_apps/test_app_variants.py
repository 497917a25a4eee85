"""Real app-export variants that failed before issue 31, written from each app's published layout.

phyphox simple-experiment tables (``"Time (s)","X (m/s^2)",...``), a custom experiment
naming gravity-including acceleration "linear", an unrecognised zip, old Sensor Logger
tables (``time,z,y,x``), ``info --format``, AndroSensor's ``sep=;`` CSV and Physics
Toolbox's multi-record (sample-and-hold) CSV.
"""

from __future__ import annotations

import contextlib
import io
import json
import zipfile

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.io import detect_format, read_recording
from gaitml.io._hold import dehold
from tests.io_apps._make import G, acc_true, gyr_true, jittered_times, write_csv

XYZ_ACC = ["Time (s)", "X (m/s^2)", "Y (m/s^2)", "Z (m/s^2)"]
XYZ_GYR = ["Time (s)", "X (rad/s)", "Y (rad/s)", "Z (rad/s)"]


def _info(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["info", *argv, "--json"])
    return code, (json.loads(out.getvalue()) if code == 0 else None), err.getvalue()


def _close_to_truth(rec, shift_s=0.0, tol=0.03):
    t = rec.meta["t0_original_s"] + rec.t_s + shift_s
    assert np.max(np.abs(rec.acc - acc_true(t))) < tol
    if rec.has_gyr:
        assert np.max(np.abs(rec.gyr - gyr_true(t))) < tol


def test_phyphox_simple_experiment_tables(tmp_path):
    d = tmp_path / "simple"
    ta, tg = jittered_times(0, 20, 100, 1), jittered_times(0.02, 19.9, 200, 2)
    write_csv(d / "Accelerometer.csv", XYZ_ACC, [ta, *acc_true(ta).T])
    write_csv(d / "Gyroscope.csv", XYZ_GYR, [tg, *gyr_true(tg).T])
    write_csv(d / "Magnetometer.csv", ["Time (s)", "X (µT)", "Y (µT)", "Z (µT)"], [ta, ta, ta, ta])
    assert detect_format(d) == "phyphox" and detect_format(d / "Accelerometer.csv") == "phyphox"
    rec = read_recording(d)
    assert rec.has_gyr and rec.meta["clock_merge"]["gyr_rate_hz"] == pytest.approx(200, rel=0.02)
    _close_to_truth(rec)


def test_phyphox_linear_tables_refused_and_gravity_named_linear_accepted(tmp_path):
    ta = jittered_times(0, 20, 100, 1)
    lin = tmp_path / "lin"
    write_csv(lin / "Linear Accelerometer.csv", XYZ_ACC, [ta, *(acc_true(ta) - [0, 0, G]).T])
    with pytest.raises(InputError, match="only linear acceleration"):
        read_recording(lin)
    custom = tmp_path / "custom"
    cols = ["Time (s)", *(f"Linear Acceleration {a} (m/s^2)" for a in "xyz")]
    write_csv(custom / "Accelerometer.csv", cols, [ta, *acc_true(ta).T])
    rec = read_recording(custom)
    assert "gravity included" in rec.meta["acc_source"]
    _close_to_truth(rec)


def test_unrecognised_zip_names_what_it_holds(tmp_path):
    z = tmp_path / "export.zip"
    with zipfile.ZipFile(z, "w") as f:
        f.writestr("notes.txt", "x")
        f.writestr("data.json", "{}")
    with pytest.raises(InputError, match=r"zip archive gaitml does not recognise \(no CSV tables; it holds notes.txt, data.json\)") as e:
        detect_format(z)
    assert "Excel" not in str(e.value)


def test_old_sensor_logger_tables_and_info_format(tmp_path):
    d = tmp_path / "old"
    ta, tg = jittered_times(0, 20, 100, 1), jittered_times(0.02, 19.9, 200, 2)
    a, g = acc_true(ta), gyr_true(tg)
    t0 = 1_700_000_000_000_000_000
    write_csv(d / "TotalAcceleration.csv", ["time", "z", "y", "x"], [(t0 + ta * 1e9).astype(np.int64), a[:, 2], a[:, 1], a[:, 0]])
    write_csv(d / "Gyroscope.csv", ["time", "z", "y", "x"], [(t0 + tg * 1e9).astype(np.int64), g[:, 2], g[:, 1], g[:, 0]])
    assert detect_format(d) == "sensor-logger"
    rec = read_recording(d)
    _close_to_truth(rec, shift_s=0.0)
    code, desc, _ = _info([str(d / "TotalAcceleration.csv"), "--format", "sensor-logger"])
    assert code == 0 and desc["kind"] == "recording" and desc["format"] == "sensor-logger"


def _androsensor(path, interval_ms):
    t = np.arange(0, 20, interval_ms / 1000)
    a, g = acc_true(t), gyr_true(t)
    lines = [
        "sep=;",
        "ACCELEROMETER X (m/s²);ACCELEROMETER Y (m/s²);ACCELEROMETER Z (m/s²);GYROSCOPE X (rad/s);GYROSCOPE Y (rad/s);"
        "GYROSCOPE Z (rad/s);Time since start in ms ;YYYY-MO-DD HH-MI-SS_SSS",
    ]
    for i, ti in enumerate(t):
        vals = ";".join(f"{v:.4f}" for v in (*a[i], *g[i]))
        lines.append(f"{vals};{int(round(ti * 1000))};2024-01-01 10-00-{int(ti):02d}_{int(round(ti * 1000)) % 1000:03d}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


ANDRO_COLS = "t=Time since start in ms,acc_x=0,acc_y=1,acc_z=2,gyr_x=3,gyr_y=4,gyr_z=5"


def test_androsensor_csv_through_columns(tmp_path):
    p = _androsensor(tmp_path / "Sensor_record.csv", 20)
    rec = read_recording(p, columns=ANDRO_COLS, time_unit="ms")
    assert rec.sampling_rate_hz == pytest.approx(50) and "sep=" in rec.meta["dialect"]
    _close_to_truth(rec)
    slow = _androsensor(tmp_path / "slow.csv", 500)  # AndroSensor's default 0.5 s interval
    with pytest.raises(InputError, match=r"read in ms\), too slow for gait .*recording interval") as e:
        read_recording(slow, columns=ANDRO_COLS, time_unit="ms")
    assert "--time-unit with one of s, us, ns" in str(e.value)


def _multirecord(path, acc_rate, gyr_rate, other_rate=20.0, seconds=30.0):
    """Physics Toolbox multi-record: one row per event of any sensor, the others repeating their last value."""
    rng = np.random.default_rng(0)
    ev = []
    for kind, rate in (("a", acc_rate), ("g", gyr_rate), ("m", other_rate)):
        n = int(seconds * rate)
        ev += [(k / rate + rng.uniform(0, 0.3 / rate), kind) for k in range(n)]
    ev.sort()
    ta = np.array([t for t, k in ev if k == "a"])
    tg = np.array([t for t, k in ev if k == "g"])
    a, g = acc_true(ta) / 9.81, gyr_true(tg)
    ia = ig = -1
    rows = ["time,gFx,gFy,gFz,wx,wy,wz,Bx,By,Bz"]
    for t, k in ev:
        ia += k == "a"
        ig += k == "g"
        if ia >= 0 and ig >= 0:
            rows.append(f"{t:.4f},{a[ia, 0]:.4f},{a[ia, 1]:.4f},{a[ia, 2]:.4f},{g[ig, 0]:.4f},{g[ig, 1]:.4f},{g[ig, 2]:.4f},1,2,3")
    path.write_text("\n".join(rows) + "\n")
    return path


def test_physics_toolbox_multirecord_read_at_update_rate(tmp_path):
    p = _multirecord(tmp_path / "ptb.csv", acc_rate=14.7, gyr_rate=30.0)
    code, desc, err = _info([str(p), "--columns", "t=time,acc_x=gFx,acc_y=gFy,acc_z=gFz,gyr_x=wx,gyr_y=wy,gyr_z=wz", "--acc-unit", "g"])
    assert code == 0, err
    hold = desc["sample_and_hold"]
    assert hold["acc"]["update_rate_hz"] == pytest.approx(14.7, rel=0.03)
    assert hold["acc"]["row_rate_hz"] > 3 * 14.7 * 0.9
    assert desc["original_rate_hz"] == pytest.approx(14.7, rel=0.05)
    assert any("sample-and-hold" in w for w in desc["warnings"])


def test_dehold_leaves_a_real_stream_alone():
    t = np.arange(1000) / 100.0
    x = acc_true(t) + np.random.default_rng(1).normal(0, 0.01, (1000, 3))
    x[500:520] = x[500]  # a short flat stretch (clipping, rest) is not sample-and-hold
    t2, x2, info = dehold(t, x, "accelerometer")
    assert info is None and len(t2) == 1000


def test_androsensor_without_columns_names_the_fix(tmp_path):
    p = _androsensor(tmp_path / "Sensor_record.csv", 20)
    with pytest.raises(InputError, match=r"separator hint 'sep=;'.*--columns"):
        detect_format(p)


def test_sample_and_hold_gaitml_csv_read_at_update_rate(tmp_path):
    t = np.arange(0, 20, 0.005)  # rows at 200 Hz
    tu = np.arange(0, 20, 0.04)  # the sensor updates at 25 Hz
    held = acc_true(tu)[np.searchsorted(tu, t, side="right") - 1]
    p = tmp_path / "held.csv"
    np.savetxt(p, np.column_stack([t, held]), delimiter=",", header="t,acc_x,acc_y,acc_z", comments="", fmt="%.6f")
    rec = read_recording(p)
    assert rec.sampling_rate_hz == pytest.approx(25.0) and rec.meta["sample_and_hold"]["acc"]["row_rate_hz"] == pytest.approx(200.0)
    _close_to_truth(rec, tol=0.05)


def test_dehold_leaves_constant_and_long_still_stretches_alone():
    t = np.arange(2000) / 100.0
    const = np.tile([0.0, 0.0, 9.81], (2000, 1))
    assert dehold(t, const, "accelerometer")[2] is None
    still_half = acc_true(t) + np.random.default_rng(2).normal(0, 0.01, (2000, 3))
    still_half[:1000] = still_half[0]  # 10 s lying still with a sensor that reports the same value
    assert dehold(t, still_half, "accelerometer")[2] is None
