"""GetSensorData logs written from the published line format (app log header, IPIN annexes)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.io import detect_format, read_recording
from gaitml.io.getsensordata import read_getsensordata_landmarks, scan_getsensordata, write_getsensordata
from tests.io_apps._make import acc_true, gyr_true, jittered_times

OTHER = [
    "MAGN;1.000;1001.000;10.0;20.0;30.0;3",
    "PRES;2.000;1002.000;1013.2;0",
    "LIGH;2.500;1002.500;120.0;0",
    "PROX;2.600;1002.600;5.0;0",
    "AHRS;3.000;1003.000;1.0;2.0;90.0;0.1;0.2;0.3;0",
    "GNSS;3.500;1700000000.000;40.4;-3.7;650.0;0.0;5.0;0.0;12;8",
    "WIFI;4.000;4.000;eduroam;00:11:22:33:44:55;2412;-70",
    "BLUE;4.500;beacon;AA:BB:CC:DD:EE:FF;-80",
    "SOUN;5.000;0.01;0.02;60.0",
]


def _log(path, *, duration_s=30.0, gyro=True, gyr_origin=None, other=True, landmarks=True):
    ta = jittered_times(0.0, duration_s, 100.0, seed=1)
    tg = jittered_times(0.05, duration_s + 0.2, 200.0, seed=2)
    lm = pd.DataFrame(
        {"t_s": [1.0, 10.0, 20.0, 29.0], "lat_deg": [40.0, 40.0001, 40.0002, 40.0003], "lon_deg": [-3.7] * 4, "floor": [0, 0, 1, 1]}
    )
    write_getsensordata(
        path,
        ta,
        acc_true(ta),
        t_gyr_s=tg if gyro else None,
        gyr=gyr_true(tg) if gyro else None,
        gyr_sensor_origin_s=gyr_origin,
        landmarks=lm if landmarks else None,
        extra_lines=OTHER if other else None,
    )
    return path, ta, tg


def test_every_line_type_read_and_counted(tmp_path):
    p, ta, tg = _log(tmp_path / "walk.txt")
    assert detect_format(p) == "getsensordata"
    rec = read_recording(p)
    gsd = rec.meta["getsensordata"]
    # sample counts against the raw lines
    raw = p.read_text().splitlines()
    assert gsd["ACCE"]["events"] == sum(line.startswith("ACCE;") for line in raw) == len(ta)
    assert gsd["GYRO"]["events"] == sum(line.startswith("GYRO;") for line in raw) == len(tg)
    assert gsd["ACCE"]["rate_hz"] == pytest.approx(100, rel=0.02) and gsd["GYRO"]["rate_hz"] == pytest.approx(200, rel=0.02)
    other = rec.meta["other_sensors"]
    assert set(other) == {line[:4] for line in OTHER} and all(v["lines"] == 1 and not v["kept"] for v in other.values())
    assert rec.has_gyr and rec.sampling_rate_hz == pytest.approx(100, rel=0.02)
    # merged clock: grid times on the sensor clock, compared with the analytic signal (values written with 5 decimals,
    # times with 1 ms resolution: a 2 Hz, 2 m/s^2 bounce moves by <= 0.013 m/s^2 in 0.5 ms)
    t_true = rec.meta["t0_original_s"] + rec.t_s - gsd["ACCE"]["offset_s"] - 1000.0
    assert np.max(np.abs(rec.acc - acc_true(t_true))) < 0.05
    assert np.max(np.abs(rec.gyr - gyr_true(t_true))) < 0.01
    lm = rec.reference["landmarks"]
    assert list(lm["floor"]) == [0, 0, 1, 1]
    # landmarks on the recording's time base: POSI time minus the first sample's app time
    assert lm["t_s"].iloc[0] == pytest.approx(1.0 - rec.meta["t0_original_s"], abs=1e-9)


def test_separate_sensor_clocks_each_get_their_own_offset(tmp_path):
    p, _, _ = _log(tmp_path / "walk.txt", gyr_origin=500.0)
    rec = read_recording(p)
    assert "separate sensor clocks" in rec.meta["getsensordata"]["clock_rule"]
    t_true = rec.meta["t0_original_s"] + rec.t_s - rec.meta["getsensordata"]["ACCE"]["offset_s"] - 1000.0
    assert np.max(np.abs(rec.gyr - gyr_true(t_true))) < 0.01


def test_missing_gyroscope_reads_accelerometer_with_warning(tmp_path):
    p, ta, _ = _log(tmp_path / "walk.txt", gyro=False)
    rec = read_recording(p)
    assert not rec.has_gyr and rec.meta["getsensordata"]["ACCE"]["events"] == len(ta)
    assert any("no GYRO" in w for w in rec.meta["warnings"])


def test_out_of_order_and_repeated_events(tmp_path):
    p, ta, _ = _log(tmp_path / "walk.txt", other=False, landmarks=False)
    lines = p.read_text().splitlines()
    acce = [i for i, line in enumerate(lines) if line.startswith("ACCE;")]
    i, j = acce[100], acce[101]
    lines[i], lines[j] = lines[j], lines[i]  # two events swapped
    lines.insert(acce[200] + 1, lines[acce[200]])  # one event repeated
    p.write_text("\n".join(lines) + "\n")
    rec = read_recording(p)
    info = rec.meta["getsensordata"]["ACCE"]
    assert info["reordered"] == 1 and info["duplicates"] == 1 and info["events"] == len(ta) + 1
    assert rec.meta["n_original_samples"] <= len(ta)


def test_restarted_clock_refused_with_line(tmp_path):
    p = tmp_path / "walk.txt"
    rows = [f"ACCE;{k * 0.01:.3f};{100 + k * 0.01:.3f};0;0;9.8;3" for k in range(300)]
    rows[200] = "ACCE;2.000;50.000;0;0;9.8;3"
    p.write_text("\n".join(rows) + "\n")
    with pytest.raises(InputError, match=r"line 201 .*restarted sensor clock"):
        read_recording(p)


@pytest.mark.parametrize(
    ("bad", "why"),
    [
        ("ACCE;1.0;1001.0;0.1;x;9.8;3", "not a number"),
        ("ACCE;1.0;1001.0;0.1;9.8", "6 or 7 fields"),
        ("ACCE;1.0;1001.0;0.1;0.2;9.8;3;4;5", "6 or 7 fields"),
        ("garbage line", "not a TYPE"),
        ("POSI;1.0;1;40.0", "bad POSI"),
    ],
)
def test_malformed_line_refused_with_its_number(tmp_path, bad, why):
    p, _, _ = _log(tmp_path / "walk.txt", other=False, landmarks=False, duration_s=5.0)
    lines = p.read_text().splitlines()
    lines.insert(50, bad)
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=rf"line 51 is malformed \(.*{why}"):
        read_recording(p, format="getsensordata")


def test_cut_short_last_line_dropped_with_warning(tmp_path):
    p, ta, _ = _log(tmp_path / "walk.txt", other=False, landmarks=False, gyro=False, duration_s=5.0)
    p.write_text(p.read_text() + "ACCE;9.99;10\n")
    rec = read_recording(p)
    assert rec.meta["getsensordata"]["ACCE"]["events"] == len(ta)
    assert any("last line" in w for w in rec.meta["warnings"])


def test_blocks_give_the_same_arrays(tmp_path):
    p, _, _ = _log(tmp_path / "walk.txt", duration_s=10.0)
    whole = scan_getsensordata(p)
    small = scan_getsensordata(p, block_bytes=2000)
    for a, b in zip(whole.acce, small.acce, strict=True):
        np.testing.assert_array_equal(a, b)
    assert whole.other == small.other and len(whole.posi) == len(small.posi) == 4


def test_landmarks_alone_and_no_accelerometer(tmp_path):
    p, _, _ = _log(tmp_path / "walk.txt", duration_s=5.0)
    lm = read_getsensordata_landmarks(p)
    assert list(lm["t_s"]) == [1.0, 10.0, 20.0, 29.0]
    q = tmp_path / "wifi.txt"
    q.write_text("% LogFile created by the 'GetSensorData' App\n" + "\n".join(OTHER[6:]) + "\n")
    with pytest.raises(InputError, match="no ACCE"):
        read_recording(q)
