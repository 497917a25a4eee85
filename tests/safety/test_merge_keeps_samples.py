"""Issue 28 finding 3: merged clocks keep every accelerometer sample, say what was filled, and `label` keeps the time base."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.cli import main
from gaitml.io import read_recording
from tests.io_apps._make import acc_true, phyphox_export


def test_short_gyroscope_table_keeps_the_whole_walk(tmp_path, capsys):
    # a 60 s walk whose gyroscope table covers only 20-30 s
    d = phyphox_export(tmp_path / "walk", duration_s=60.0, gyr_offset_s=20.0, gyr_end_s=30.0)
    rec = read_recording(d)
    assert rec.duration_s > 59.9  # was 10 s: 83 % of the accelerometer dropped
    assert rec.meta["t0_original_s"] < 0.02  # was 20 s: t = 0 moved
    merge = rec.meta["clock_merge"]
    assert merge["dropped_acc_samples"] == 0
    (a0, a1), (b0, b1) = merge["gyr_filled_s"]
    assert a0 < 0.02 and abs(a1 - 20.0) < 0.02 and abs(b0 - 30.0) < 0.02 and b1 > 59.9
    # the accelerometer is the measured one everywhere
    t = rec.meta["t0_original_s"] + rec.t_s
    assert np.max(np.abs(rec.acc - acc_true(t))) < 0.02
    # every command prints the one warning line
    assert main(["steps", str(d)]) == 0
    err = capsys.readouterr().err
    assert sum("filled there" in line for line in err.splitlines()) == 1


def test_sensors_started_together_are_silent(tmp_path):
    d = phyphox_export(tmp_path / "walk", duration_s=20.0, gyr_offset_s=0.01, gyr_end_s=19.99)
    rec = read_recording(d)
    assert not rec.meta.get("warnings")


def test_label_keeps_the_persons_time_base(tmp_path, capsys):
    d = phyphox_export(tmp_path / "walk", duration_s=60.0, gyr_offset_s=20.0, gyr_end_s=30.0)
    iv = tmp_path / "iv.csv"
    iv.write_text("start_s,end_s,label\n40,50,run\n")
    out = tmp_path / "labelled.csv"
    assert main(["label", str(d), "--intervals", str(iv), "--snap", "none", "--out", str(out)]) == 0
    table = pd.read_csv(out)
    run = table.loc[table["label"] == "run", "t"].to_numpy()
    # the person's 40-50 s are the export's 40-50 s (they were 60-70 s of a clock that started at the gyroscope)
    assert abs(run.min() - 40.0) < 0.05 and abs(run.max() - 50.0) < 0.05
