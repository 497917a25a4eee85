"""`gaitml label`: outputs, the per-step table, errors leave no files."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.io import read_dataset, read_recording, write_gaitml_csv
from gaitml.labels import intervals_from_labels, perturb_intervals
from gaitml.simulate import simulate_dataset


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("label")
    rec = simulate_dataset(n_subjects=1, duration_s=40.0, seed=2)[0]
    write_gaitml_csv(rec.replace(labels=None), d / "rec.csv")
    iv = perturb_intervals(intervals_from_labels(rec.labels, rec.sampling_rate_hz), 0.3, np.random.default_rng(5), rec.duration_s)
    with open(d / "labels.txt", "w") as fh:
        for row in iv.itertuples():
            fh.write(f"{row.start_s:.6f}\t{row.end_s:.6f}\t{row.label}\n")
    return d, rec


def test_label_writes_recording_step_table_and_report(files, tmp_path, capsys):
    d, rec = files
    out = tmp_path / "out" / "walk.labelled.csv"
    code = main(["label", str(d / "rec.csv"), "--intervals", str(d / "labels.txt"), "--out", str(out), "--report", str(tmp_path / "r.png")])
    text = capsys.readouterr().out
    assert code == 0 and f"snapped to steps of {DEFAULT_STEP_DETECTOR}" in text
    lab = read_recording(out)
    assert lab.n_samples == rec.n_samples and np.mean(lab.labels == rec.labels) > 0.99
    np.testing.assert_array_equal(lab.acc, rec.acc)  # lossless writer
    steps = pd.read_csv(tmp_path / "out" / "walk.labelled.step-labels.csv")
    assert list(steps.columns) == ["step", "t_s", "span_start_s", "span_end_s", "label", "label_fraction"]
    assert set(steps["label"]) <= set(rec.labels) | {"unlabelled"}
    assert (tmp_path / "r.png").read_bytes()[:4] == b"\x89PNG"
    # the per-step table is a sidecar, not ground truth and not a recording of the folder
    assert "steps_t_s" not in lab.reference
    assert len(read_dataset(tmp_path / "out")) == 1


def test_label_json_and_snap_none(files, tmp_path, capsys):
    d, _ = files
    out = tmp_path / "o.csv"
    code = main(["label", str(d / "rec.csv"), "--intervals", str(d / "labels.txt"), "--snap", "none", "--out", str(out), "--json"])
    obj = json.loads(capsys.readouterr().out)
    assert code == 0 and obj["snap"] == "none" and obj["n_snapped"] == 0 and obj["n_intervals"] == len(obj["intervals"])


def test_overlapping_intervals_exit_2_without_outputs(files, tmp_path, capsys):
    d, _ = files
    bad = tmp_path / "bad.csv"
    bad.write_text("start_s,end_s,label\n0,10,walk\n9,20,run\n")
    out = tmp_path / "o.csv"
    code = main(["label", str(d / "rec.csv"), "--intervals", str(bad), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "intervals overlap" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == [bad]


def test_strides_need_a_gyroscope_and_a_zupt_detector(files, tmp_path, capsys):
    d, _ = files
    code = main(
        [
            "label",
            str(d / "rec.csv"),
            "--intervals",
            str(d / "labels.txt"),
            "--snap",
            "strides",
            "--detector",
            "ifsm",
            "--out",
            str(tmp_path / "o.csv"),
        ]
    )
    assert code == 2 and "unknown zero-velocity detector 'ifsm'" in capsys.readouterr().err


def test_out_must_be_csv(files, tmp_path, capsys):
    d, _ = files
    assert main(["label", str(d / "rec.csv"), "--intervals", str(d / "labels.txt"), "--out", str(tmp_path / "o.txt")]) == 2
    assert "must be a .csv" in capsys.readouterr().err


def test_phone_export_to_labelled_recording(tmp_path, capsys):
    """The whole path: a phyphox export (acc and gyro on their own jittered clocks) -> gaitml label."""
    from tests.io_apps._make import PHY_ACC, PHY_GYR, write_csv

    rec = simulate_dataset(n_subjects=1, duration_s=40.0, seed=4, sampling_rate_hz=100.0)[0]
    t = rec.t_s
    rng = np.random.default_rng(0)
    ta = t[1:-1] + rng.uniform(-0.002, 0.002, len(t) - 2)
    tg = np.arange(0.013, t[-1] - 0.05, 0.005)
    acc = np.column_stack([np.interp(ta, t, rec.acc[:, j]) for j in range(3)])
    gyr = np.column_stack([np.interp(tg, t, rec.gyr[:, j]) for j in range(3)])
    export = tmp_path / "export"
    write_csv(export / "Accelerometer.csv", PHY_ACC, [ta, *acc.T, np.linalg.norm(acc, axis=1)])
    write_csv(export / "Gyroscope.csv", PHY_GYR, [tg, *gyr.T, np.linalg.norm(gyr, axis=1)])
    (export / "meta").mkdir()
    (export / "meta" / "device.csv").write_text('"property","value"\n')
    # the person's notes, on the app's clock (the export's t = 0)
    iv = perturb_intervals(intervals_from_labels(rec.labels, rec.sampling_rate_hz), 0.3, np.random.default_rng(9), rec.duration_s)
    t0 = float(ta[0])  # the labelled recording starts at the first accelerometer sample
    iv["start_s"] = np.clip(iv["start_s"] - t0, 0, None)
    iv["end_s"] = np.minimum(iv["end_s"] - t0, t[-1] - 0.06 - t0)
    iv.to_csv(tmp_path / "iv.csv", index=False, columns=["start_s", "end_s", "label"])
    out = tmp_path / "walk.csv"
    assert main(["label", str(export), "--intervals", str(tmp_path / "iv.csv"), "--out", str(out), "--detector", "adfsm"]) == 0
    lab = read_recording(out)
    assert lab.has_gyr and lab.sampling_rate_hz == pytest.approx(100.0, rel=0.01)
    truth = rec.labels[np.clip(np.round((t0 + lab.t_s) * 100).astype(int), 0, rec.n_samples - 1)]
    assert np.mean(lab.labels == truth) > 0.98  # 0.9995 measured
