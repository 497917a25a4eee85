"""Readers: format detection, gaitml-csv round trip, the shared real data sets."""

from __future__ import annotations

import gzip
import shutil

import numpy as np
import pandas as pd
import pytest

from gaitml import InputError
from gaitml.consts import GRAVITY_MS2
from gaitml.io import detect_format, read_dataset, read_recording, write_gaitml_csv, write_manifest
from gaitml.recording import Recording
from tests.conftest import shared


def _rec(n=200, fs=50.0, gyr=True, labels=True, seed=0):
    rng = np.random.default_rng(seed)
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, GRAVITY_MS2]
    return Recording(
        acc=acc,
        gyr=rng.normal(0, 0.5, (n, 3)) if gyr else None,
        labels=rng.choice(["walk", "run"], n) if labels else None,
        sampling_rate_hz=fs,
    )


@pytest.mark.parametrize("fs", [50.0, 100.0, 204.8, 97.3])
def test_gaitml_csv_round_trip_is_lossless(tmp_path, fs):
    rec = _rec(fs=fs)
    path = write_gaitml_csv(rec, tmp_path / "r.csv")
    back = read_recording(path)
    assert back.sampling_rate_hz == fs
    np.testing.assert_array_equal(back.acc, rec.acc)
    np.testing.assert_array_equal(back.gyr, rec.gyr)
    np.testing.assert_array_equal(back.labels, rec.labels)
    assert back.meta["format"] == "gaitml-csv"
    assert back.meta["resampled"] is False


def test_gaitml_csv_without_gyro_and_labels(tmp_path):
    rec = _rec(gyr=False, labels=False)
    back = read_recording(write_gaitml_csv(rec, tmp_path / "a.csv"))
    assert back.gyr is None and back.labels is None


def test_gaitml_csv_irregular_is_resampled(tmp_path):
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.008, 0.012, 500))
    df = pd.DataFrame({"t": t, "acc_x": np.sin(t), "acc_y": 0.0, "acc_z": GRAVITY_MS2, "temp": 20.0})
    df.to_csv(tmp_path / "irr.csv", index=False)
    rec = read_recording(tmp_path / "irr.csv")
    assert rec.meta["resampled"] is True
    assert rec.meta["ignored_columns"] == ["temp"]
    assert rec.sampling_rate_hz == pytest.approx(100, rel=0.05)
    rec2 = read_recording(tmp_path / "irr.csv", sampling_rate_hz=50.0)
    assert rec2.sampling_rate_hz == 50.0


def test_folder_with_manifest(tmp_path):
    rows = []
    for i in range(3):
        write_gaitml_csv(_rec(seed=i), tmp_path / f"r{i}.csv")
        rows.append({"file": f"r{i}.csv", "subject": f"S{i % 2}", "session": f"s{i}", "height_m": 1.7})
    write_manifest(rows, tmp_path)
    recs = read_dataset(tmp_path)
    assert [r.meta["subject"] for r in recs] == ["S0", "S1", "S0"]
    assert recs[0].meta["height_m"] == 1.7
    assert detect_format(tmp_path) == "gaitml-folder"


def test_manifest_naming_missing_file(tmp_path):
    write_gaitml_csv(_rec(), tmp_path / "r0.csv")
    write_manifest([{"file": "r0.csv", "subject": "a", "session": "1"}, {"file": "gone.csv", "subject": "b", "session": "1"}], tmp_path)
    with pytest.raises(InputError, match="manifest.csv names a missing file: gone.csv"):
        read_dataset(tmp_path)


def test_sidecars_become_reference(tmp_path):
    write_gaitml_csv(_rec(), tmp_path / "sim.csv")
    pd.DataFrame({"t_s": [0.5, 1.0], "mode": ["walk", "walk"]}).to_csv(tmp_path / "sim.steps.csv", index=False)
    rec = read_recording(tmp_path / "sim.csv")
    np.testing.assert_allclose(rec.reference["steps_t_s"], [0.5, 1.0])
    assert len(read_dataset(tmp_path)) == 1  # the sidecar is not a recording


@pytest.mark.parametrize(
    "content, match",
    [
        ("", "empty"),
        ("a,b,c\n1,2,3\n", "unknown format"),
        ("t,acc_x,acc_y,acc_z\n", "no samples"),
        ("t,acc_x,acc_y,acc_z\n0,1,2,9.8\n0.01,nan,2,9.8\n", "NaN/inf"),
        ("t,acc_x,acc_y,acc_z\n0,1,2,9.8\n0.01,inf,2,9.8\n", "NaN/inf"),
        ("t,acc_x,acc_y,acc_z\n0,1,2,9.8\n0.01,x,2,9.8\n", "non-numeric value at line 3"),
        ("t,acc_x,acc_y,acc_z\n0,1,2,9.8\n0,1,2,9.8\n0.02,1,2,9.8\n", "duplicate timestamp"),
        ("t,acc_x,acc_y,acc_z\n0,1,2,9.8\n0.02,1,2,9.8\n0.01,1,2,9.8\n", "timestamps decrease"),
        ("t,acc_x,acc_y,acc_z,gyr_x\n0,1,2,9.8,1\n0.01,1,2,9.8,1\n", "only \\['gyr_x'\\]"),
    ],
)
def test_bad_gaitml_csv(tmp_path, content, match):
    p = tmp_path / "bad.csv"
    p.write_text(content)
    with pytest.raises(InputError, match=match):
        read_recording(p)


def test_acc_in_g_detected_in_file(tmp_path):
    rec = _rec()
    df = pd.DataFrame({"t": rec.t_s, "acc_x": rec.acc[:, 0] / 9.81, "acc_y": rec.acc[:, 1] / 9.81, "acc_z": rec.acc[:, 2] / 9.81})
    df.to_csv(tmp_path / "g.csv", index=False)
    with pytest.raises(InputError, match="in g"):
        read_recording(tmp_path / "g.csv")
    assert read_recording(tmp_path / "g.csv", acc_unit="g").acc[:, 2].mean() == pytest.approx(GRAVITY_MS2, rel=0.1)


def test_missing_file():
    with pytest.raises(InputError, match="no such file"):
        read_recording("/nonexistent/x.csv")


# ----------------------------------------------------------------- real data
@pytest.mark.realdata
@pytest.mark.parametrize("name, n", [("acceleration_flat_holding_1.xlsx", 7197), ("acceleration_flat_holding_2.xlsx", 8379)])
def test_ifsm_files(name, n):
    rec = read_recording(shared("ifsm-flat-phone", name))
    assert rec.n_samples == n and rec.sampling_rate_hz == 50.0
    assert rec.meta["format"] == "ifsm-xlsx"
    assert rec.reference["n_steps_true"] == {7197: 284, 8379: 319}[n]


@pytest.mark.realdata
def test_gaitmap_imu_sample_both_feet():
    p = shared("gaitmap-example", "imu_sample.csv.gz")
    left = read_recording(p, sensor="left")
    right = read_recording(p, sensor="right")
    assert left.n_samples == right.n_samples == 7928
    assert left.sampling_rate_hz == 204.8
    assert len(left.reference["strides"]) == 28 and len(right.reference["strides"]) == 30
    assert len(left.reference["stride_events"]) == 28 and len(right.reference["stride_events"]) == 29
    assert np.abs(left.gyr).max() < 20  # rad/s after conversion from deg/s
    raw = pd.read_csv(p, header=[0, 1], index_col=0)
    np.testing.assert_allclose(left.gyr[:, 2], np.deg2rad(raw["left_sensor"]["gyr_z"].to_numpy()))


@pytest.mark.realdata
def test_gaitmap_other_files_rates():
    assert read_recording(shared("gaitmap-example", "imu_sample_healthy_stair_up.csv.gz")).sampling_rate_hz == pytest.approx(204.8)
    assert read_recording(shared("gaitmap-example", "imu_sample_ms_left.csv.gz")).sampling_rate_hz == pytest.approx(102.4)
    assert read_recording(shared("gaitmap-example", "imu_sample_ic_stride.csv.gz")).n_samples == 4053


@pytest.mark.realdata
def test_oxford_folder_resampled_with_step_times():
    rec = read_recording(shared("oxford-step-counter", "optimisation", "data", "Samsung_Dario_Hard_Purse_1"))
    assert rec.sampling_rate_hz == 100.0
    assert rec.meta["resampled"] is True and rec.meta["position"] == "Purse" and rec.meta["user"] == "Dario"
    assert 200 < rec.meta["original_rate_hz"] < 215
    steps = rec.reference["steps_t_s"]
    assert np.all(np.diff(steps) >= 0) and steps[0] >= 0 and steps[-1] <= rec.duration_s


@pytest.mark.realdata
def test_oxford_all_folders_match_stats():
    root = shared("oxford-step-counter", "optimisation")
    stats = pd.read_csv(root / "stats.csv", skipinitialspace=True)
    stats.columns = [c.strip().lstrip("#") for c in stats.columns]
    from gaitml.io.oxford import oxford_step_times_ns

    total = 0
    for d in stats["dir"].str.strip():
        states = pd.read_csv(root / "data" / d / "stepcounter.csv", header=None).to_numpy()
        total += len(oxford_step_times_ns(states))
    assert total == int(stats["steps"].sum()) == 13740


@pytest.mark.realdata
def test_truncated_gzip_is_an_input_error(tmp_path):
    src = shared("gaitmap-example", "imu_sample.csv.gz")
    data = src.read_bytes()
    (tmp_path / "imu_sample.csv.gz").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError):
        read_recording(tmp_path / "imu_sample.csv.gz")


@pytest.mark.realdata
def test_truncated_oxford_folder(tmp_path):
    src = shared("oxford-step-counter", "optimisation", "data", "Samsung_Jamie_Hard_InHand_1")
    dst = tmp_path / "Samsung_Jamie_Hard_InHand_1"
    shutil.copytree(src, dst)
    with gzip.open(dst / "accelerometer.csv.gz", "rt") as fh:
        lines = fh.read().splitlines()
    with gzip.open(dst / "accelerometer.csv.gz", "wt") as fh:
        fh.write("\n".join(lines[:1000]) + "\n" + lines[1000][:12] + "\n")
    with pytest.raises(InputError, match="truncated|columns|non-numeric"):
        read_recording(dst)


# ---------------------------------------------------------------- issue 17: dialects, odd headers, segments
def _walk_frame(n=500, fs=50.0):
    rng = np.random.default_rng(5)
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, GRAVITY_MS2]
    return pd.DataFrame({"t": np.arange(n) / fs, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2], "label": "walk"})


@pytest.mark.parametrize(
    "write",
    [
        lambda df, p: p.write_text("\ufeff" + df.to_csv(index=False), encoding="utf-8"),
        lambda df, p: p.write_text(df.to_csv(index=False).replace("\n", "\r\n"), encoding="utf-8"),
        lambda df, p: df.to_csv(p, index=False, sep=";"),
        lambda df, p: df.to_csv(p, index=False, sep=";", decimal=","),
        lambda df, p: df.to_csv(p, index=False, sep="\t", decimal=","),
    ],
    ids=["bom", "crlf", "semicolon", "semicolon-decimal-comma", "tab-decimal-comma"],
)
def test_spreadsheet_dialects_read_the_same(tmp_path, write):
    df = _walk_frame()
    p = tmp_path / "r.csv"
    write(df, p)
    assert detect_format(p) == "gaitml-csv"
    rec = read_recording(p)
    np.testing.assert_allclose(rec.acc, df[["acc_x", "acc_y", "acc_z"]].to_numpy(), rtol=1e-12)
    assert rec.sampling_rate_hz == 50.0 and set(rec.labels) == {"walk"}


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("t,acc_x,acc_y,acc_z\n0,01,0,2,9,8\n0,02,0,2,9,8\n", "more fields than the header"),
        ('t,acc_x,acc_y,acc_z\n"0,01","0,2","0,1","9,8"\n', r"decimal comma '0,01'"),
        ("t,acc_x,acc_y,acc_x\n0,1,2,9.8\n0.02,1,2,9.8\n", "column 'acc_x' more than once"),
        ("t,acc_x,acc_y,acc_z\n2024-01-01 10:00,1,2,9.8\n", "not a number of seconds"),
        ("t,gyr_x,gyr_y,gyr_z\n0,1,2,3\n", r"missing columns \['acc_x', 'acc_y', 'acc_z'\]"),
        ("t,acc_x," + "y" * 100_000 + ",acc_z\n0,1,2,9.8\n", r"missing columns \['acc_y'\]"),
    ],
    ids=["comma-decimal-unquoted", "comma-decimal-quoted", "duplicate", "datetime", "gyro-only", "long-header"],
)
def test_odd_csvs_are_refused_naming_the_problem(tmp_path, text, match):
    p = tmp_path / "r.csv"
    p.write_text(text)
    with pytest.raises(InputError, match=match) as exc:
        read_recording(p)
    assert "\n" not in str(exc.value) and len(str(exc.value)) < 600


def test_corrupt_gzip_is_an_input_error(tmp_path):
    p = tmp_path / "r.csv.gz"
    p.write_bytes(b"\x1f\x8b\x08\x00" + bytes(range(200)))
    with pytest.raises(InputError, match="truncated or corrupt"):
        read_recording(p)


def test_read_segments_cuts_a_file_at_long_gaps(tmp_path):
    from gaitml.io import read_segments

    df = _walk_frame(1000)
    df.loc[400:, "t"] += 3600.0  # an hour without samples
    p = tmp_path / "r.csv"
    df.to_csv(p, index=False)
    with pytest.raises(InputError, match=r"3600.02 s gap in the timestamps after sample 399"):
        read_recording(p)
    segs = read_segments(p)
    assert [s.n_samples for s in segs] == [400, 600]
    assert segs[1].meta["segment"]["t_start_s"] == pytest.approx(3608.0)
    assert [s.name for s in segs] == ["r#0", "r#1"]
    assert len(read_segments(p, sampling_rate_hz=25.0)[0].acc) == 200
