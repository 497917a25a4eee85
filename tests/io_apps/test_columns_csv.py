"""Any CSV with a column map (--columns), time units and acc units."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.io import read_columns_csv, read_recording
from tests.io_apps._make import G, acc_true, gyr_true, jittered_times, measured, write_csv


def _check(rec, t_offset=0.0):
    t = t_offset + rec.meta["t0_original_s"] + rec.t_s
    assert np.max(np.abs(rec.acc - acc_true(t))) < 0.03
    if rec.has_gyr:
        m = measured(rec)  # where the gyroscope ran (the clock merge holds its edge samples elsewhere)
        assert np.max(np.abs(rec.gyr[m] - gyr_true(t[m]))) < 0.005


def test_epoch_ms_times_and_g_units(tmp_path):
    t = jittered_times(0.0, 15.0, 100.0, seed=5)
    ms = (1_700_000_000_000 + np.round(t * 1000)).astype(np.int64)
    t_ms = (ms - ms[0]) / 1000.0
    a, g = acc_true(t_ms) / G, np.degrees(gyr_true(t_ms))
    write_csv(
        tmp_path / "log.csv", ["timestamp", "ax", "ay", "az", "gx", "gy", "gz", "activity"], [ms, *a.T, *g.T, np.array(["walk"] * len(t))]
    )
    rec = read_recording(
        tmp_path / "log.csv",
        columns="t=timestamp,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=gx,gyr_y=gy,gyr_z=gz,label=activity",
        time_unit="ms",
        acc_unit="g",
        gyr_unit="deg/s",
    )
    assert rec.meta["format"] == "columns-csv" and rec.meta["time_unit"] == "ms"
    assert set(rec.meta["converted"]) == {"acc from g", "gyr from deg/s"}
    assert rec.sampling_rate_hz == pytest.approx(100.0, rel=0.01)
    assert set(rec.labels) == {"walk"}
    _check(rec)


def test_positions_and_a_separate_gyro_clock(tmp_path):
    ta = np.arange(0, 12, 0.01)
    tg = np.arange(0.004, 11.5, 0.02)
    a, g = acc_true(ta), gyr_true(tg)
    rows = sorted([(x, "a", i) for i, x in enumerate(ta)] + [(x, "g", i) for i, x in enumerate(tg)])
    lines = ["ta;ax;ay;az;tg;gx;gy;gz"]
    for _, kind, i in rows:
        if kind == "a":
            vals = [f"{ta[i]:.9g}", *(f"{v:.9g}" for v in a[i]), "", "", "", ""]
        else:
            vals = ["", "", "", "", f"{tg[i]:.9g}", *(f"{v:.9g}" for v in g[i])]
        lines.append(";".join(v.replace(".", ",") for v in vals))
    (tmp_path / "two.csv").write_text("\n".join(lines) + "\n")
    rec = read_columns_csv(
        tmp_path / "two.csv", {"t": "0", "acc_x": "1", "acc_y": "2", "acc_z": "3", "t_gyr": "4", "gyr_x": "5", "gyr_y": "6", "gyr_z": "7"}
    )
    assert rec.has_gyr and rec.meta["clock_merge"]["overlap_s"][1] <= 11.5
    _check(rec)


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        ("t=timestamp,acc_x=ax,acc_y=ay", "lacks acc_z"),
        ("t=timestamp,acc_x=ax,acc_y=ay,acc_z=nope", "no column 'nope'"),
        ("t=timestamp,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=ax", "only gyr_x"),
        ("t=timestamp,acc_x=ax,acc_y=ay,acc_z=az,speed=ax", "unknown --columns key"),
        ("t timestamp", "has no '='"),
    ],
)
def test_bad_column_maps(tmp_path, spec, match):
    write_csv(tmp_path / "f.csv", ["timestamp", "ax", "ay", "az"], [np.arange(5) * 0.01, *acc_true(np.arange(5) * 0.01).T])
    with pytest.raises(InputError, match=match):
        read_columns_csv(tmp_path / "f.csv", spec)


def test_cli_info_reports_columns_and_merge(tmp_path, capsys):
    ta = np.arange(0, 10, 0.01)
    write_csv(tmp_path / "f.csv", ["time_us", "x", "y", "z"], [(ta * 1e6).astype(np.int64), *acc_true(ta).T])
    code = main(["info", str(tmp_path / "f.csv"), "--columns", "t=time_us,acc_x=x,acc_y=y,acc_z=z", "--time-unit", "us", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["format"] == "columns-csv" and out["sampling_rate_hz"] == pytest.approx(100.0)
    assert main(["info", str(tmp_path / "f.csv"), "--format", "columns-csv"]) == 2
    assert "--columns t=" in capsys.readouterr().err


def test_cli_info_shows_the_clock_merge(tmp_path, capsys):
    from tests.io_apps._make import phyphox_export

    d = phyphox_export(tmp_path / "p")
    assert main(["info", str(d)]) == 0
    out = capsys.readouterr().out
    assert "clock_merge" in out and "overlap" in out and "(phyphox)" in out
