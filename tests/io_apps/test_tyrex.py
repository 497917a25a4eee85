"""The tyrex attitude benchmark reader: small folders written in the data set's layout, and the real set."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.errors import InputError
from gaitml.io import detect_format, list_dataset, read_dataset, read_recording, read_segments
from gaitml.io.tyrex import estimate_mount_rotation, list_tyrex_folders, read_tyrex, read_tyrex_truth
from gaitml.pipeline.folder_source import tyrex_manifest
from tests.io_apps._make import G, acc_true, gyr_true, jittered_times, measured

BOOT_S = 5000.0


def _log(path: Path, t: np.ndarray, x: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(path, "wt") as fh:
        for ti, row in zip(t, x, strict=True):
            fh.write(f"{ti:.9f} {row[0]:.7g} {row[1]:.7g} {row[2]:.7g}\n")


def android_folder(root: Path, name: str = "Alice_Nexus5_NoDist_Texting", *, gyr_gap=None, dt_s: float = -1.5) -> Path:
    """An Android recording: m/s^2 and rad/s, times since the start, each sensor on its own jittered clock."""
    d = root / "android" / name
    t_acc = jittered_times(0.48, 30.0, 199.0, seed=1)
    t_gyr = jittered_times(0.42, 29.9, 199.0, seed=2)
    if gyr_gap is not None:
        t_gyr = t_gyr[(t_gyr < gyr_gap[0]) | (t_gyr > gyr_gap[1])]
    _log(d / "accelerometer.txt.gz", t_acc, acc_true(t_acc))
    _log(d / "gyroscope-calibrated.txt.gz", t_gyr, gyr_true(t_gyr))
    (d / "record.properties").write_text("[Device]\nManufacturer = LGE\nModel = Nexus 5\n\n[Time]\nStartTime = 1464871631\n")
    (d / "timeAlignment.txt").write_text(f"  {dt_s:.7e}\n")
    return d


def ios_folder(root: Path, name: str = "Bob_iPhone5_NoDist_Backpocket", *, dt_s: float = 2.0) -> Path:
    """An iOS recording: acceleration in g with the opposite sign, times since boot."""
    d = root / "ios" / name
    t_acc = jittered_times(0.2, 30.0, 100.0, seed=3)
    t_gyr = jittered_times(0.35, 30.1, 95.0, seed=4)
    _log(d / "accelerometer.txt.gz", t_acc + BOOT_S, -acc_true(t_acc) / G)
    _log(d / "gyroscope.txt.gz", t_gyr + BOOT_S, gyr_true(t_gyr))
    (d / "description.txt").write_text(f"[Time]\nBootTime = {BOOT_S}")
    (d / "timeAlignment.txt").write_text(f"  {dt_s:.7e}\n")
    return d


def qualisys_csv(root: Path, name: str, t_s: np.ndarray, pos_mm: np.ndarray, dcm_room_to_body: np.ndarray, lost=()) -> Path:
    """A motion-capture CSV as packed in the data set: QTM's DCM (room to body) stored row by row."""
    f = root / "qualisys" / f"{name}.csv.gz"
    f.parent.mkdir(parents=True, exist_ok=True)
    lines = [
        "# qtm_timestamp=test; frame_rate_hz=60; start_frame=1; rigid_body=test",
        "t_s,x_mm,y_mm,z_mm," + ",".join(f"rot{i}" for i in range(9)) + ",residual_mm",
    ]
    for k, t in enumerate(t_s):
        if k in lost:
            lines.append(f"{t:.4f}" + "," * 13)
            continue
        vals = [*pos_mm[k], *dcm_room_to_body[k].reshape(9)]
        lines.append(f"{t:.4f}," + ",".join(f"{v:.6f}" for v in vals) + ",0.5")
    with gzip.open(f, "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    return f


def _values_ok(rec, tol_acc=0.03, tol_gyr=0.01, gyr_span=None):
    """Samples against the written signals; the gyroscope where it ran (the merge holds its edge samples elsewhere and
    says where; a segment's own times are checked against the written gyroscope span ``gyr_span``)."""
    t = rec.meta["t0_original_s"] + rec.t_s
    assert np.max(np.abs(rec.acc - acc_true(t))) < tol_acc
    ran = measured(rec) if gyr_span is None else (t >= gyr_span[0]) & (t <= gyr_span[1])
    assert ran.mean() > 0.9
    assert np.max(np.abs(rec.gyr[ran] - gyr_true(t[ran]))) < tol_gyr


def test_android_units_meta_and_clock_merge(tmp_path):
    d = android_folder(tmp_path)
    assert detect_format(d) == "tyrex"
    assert detect_format(d / "accelerometer.txt.gz") == "tyrex"
    rec = read_recording(d)
    assert rec.meta["format"] == "tyrex" and rec.meta["platform"] == "android"
    assert rec.sampling_rate_hz == pytest.approx(199.0, rel=0.01)
    # the gyroscope starts earlier on its own clock: the merge starts at the accelerometer's first sample
    assert rec.meta["t0_original_s"] == pytest.approx(0.48)
    assert rec.meta["clock_merge"]["dropped_gyr_samples"] > 0
    _values_ok(rec)
    m = rec.meta
    assert (m["subject"], m["phone"], m["motion"], m["position"], m["mode"], m["disturbance"]) == (
        "Alice",
        "Nexus5",
        "Texting",
        "hand-texting",
        "walk",
        "NoDist",
    )
    assert m["device_model"] == "Nexus 5" and m["start_unix_s"] == 1464871631


def test_ios_g_with_opposite_sign_and_boot_time(tmp_path):
    d = ios_folder(tmp_path)
    rec = read_tyrex(d)
    assert rec.meta["platform"] == "ios"
    # t - BootTime: the first sample is the accelerometer's first, 0.2 s since the recording's start (every sample kept)
    assert rec.meta["t0_original_s"] == pytest.approx(0.2, abs=0.011)
    # -1 g on z in the file is +9.8 m/s^2 up after the conversion, the Android convention
    assert np.median(rec.acc[:, 2]) == pytest.approx(G, abs=0.3)
    _values_ok(rec)
    # the folder's case-mismatched motion is still read
    assert rec.meta["motion"] == "BackPocket" and rec.meta["position"] == "back-pocket"


def test_running_is_mode_run(tmp_path):
    d = android_folder(tmp_path, "Carl_Nexus5_NoDist_RunningPocket")
    rec = read_tyrex(d)
    assert rec.meta["mode"] == "run" and rec.meta["position"] == "pocket"


def test_gyroscope_gap_is_refused_then_read_as_segments(tmp_path):
    d = android_folder(tmp_path, gyr_gap=(10.0, 13.0))
    with pytest.raises(InputError, match=r"gyroscope has no samples from 10\.0\d to 13\.0\d s.*gaitml split"):
        read_tyrex(d)
    segs = read_segments(d)
    assert len(segs) == 2
    assert segs[0].meta["sensor_gaps"][0]["sensor"] == "gyroscope"
    t_end0 = segs[0].meta["t0_original_s"] + segs[0].t_s[-1]
    t_start1 = segs[1].meta["t0_original_s"]
    # no sample of either segment lies in the gap: nothing was bridged
    assert t_end0 <= 10.0 and t_start1 >= 13.0
    for s in segs:
        _values_ok(s, gyr_span=(0.42, 29.9))
    assert segs[1].name.endswith("#1")


def test_truth_on_the_phone_clock_case_mismatch_and_lost_markers(tmp_path):
    d = ios_folder(tmp_path, dt_s=2.0)
    t = np.arange(0, 20, 1 / 60)
    yaw = 0.3 * t
    pos = np.column_stack([1000 * np.cos(yaw), 500 + 1000 * np.sin(yaw), np.full_like(t, 1200.0)])
    body_to_room = Rotation.from_euler("z", yaw[:, None]).as_matrix()
    qualisys_csv(tmp_path, "Bob_iPhone5_NoDist_BackPocket", t, pos, np.transpose(body_to_room, (0, 2, 1)), lost=(100, 101))
    truth = read_tyrex_truth(d)
    # motion-capture time = phone time + dt
    assert truth.t_s[0] == pytest.approx(-2.0) and truth.dt_s == 2.0
    assert truth.pos_m[5] == pytest.approx(pos[5] / 1000, abs=1e-5)
    np.testing.assert_allclose(truth.rot[5], body_to_room[5], atol=1e-5)
    assert not truth.valid[100] and np.isnan(truth.pos_m[101]).all() and truth.valid.sum() == len(t) - 2
    q = truth.quat_wxyz
    assert np.isnan(q[100]).all() and abs(np.linalg.norm(q[5]) - 1) < 1e-6
    # interpolation at phone times: nothing next to a lost frame, the right attitude elsewhere
    t_q = truth.t_s[[50, 100]] + 0.004
    rot = truth.rotation_at(t_q)
    assert np.isnan(rot[1]).all()
    expect = Rotation.from_euler("z", 0.3 * (t_q[0] + 2.0)).as_matrix()
    np.testing.assert_allclose(rot[0], expect, atol=1e-4)
    pos_q = truth.position_at(t_q)
    assert np.isnan(pos_q[1]).all() and np.isfinite(pos_q[0]).all()


def test_motion_capture_file_is_not_a_recording(tmp_path):
    t = np.arange(0, 1, 1 / 60)
    f = qualisys_csv(tmp_path, "Bob_iPhone5_NoDist_Texting", t, np.zeros((len(t), 3)), np.repeat(np.eye(3)[None], len(t), axis=0))
    with pytest.raises(InputError, match="motion-capture file, not an IMU recording"):
        read_recording(f)


def test_truth_missing_is_one_line_error(tmp_path):
    d = android_folder(tmp_path)
    with pytest.raises(InputError, match="no motion capture for Alice_Nexus5_NoDist_Texting"):
        read_tyrex_truth(d)


def test_mount_rotation_recovered_from_angular_rates(tmp_path):
    """A phone turned by a known rotation from the body: the gyroscope vs motion-capture rates give it back."""
    d = android_folder(tmp_path)
    rec = read_tyrex(d)
    r_mount = Rotation.from_euler("xyz", [4.0, -3.0, 10.0], degrees=True).as_matrix()  # v_body = R v_phone
    # body attitude from integrating the body rate R_mount @ gyr(t) on the phone's clock
    t = np.arange(0.0, 29.0, 1 / 60)
    fine = np.arange(0.0, 29.0, 1 / 1200)
    w_body = gyr_true(fine) @ r_mount.T
    rots = [Rotation.identity()]
    for k in range(1, len(fine)):
        rots.append(rots[-1] * Rotation.from_rotvec(w_body[k - 1] / 1200))
    mats = Rotation.concatenate(rots)[::20].as_matrix()[: len(t)]
    qualisys_csv(tmp_path, d.name, t, np.zeros((len(t), 3)), np.transpose(mats, (0, 2, 1)))
    truth = read_tyrex_truth(d, truth_path=tmp_path / "qualisys" / f"{d.name}.csv.gz")
    # dt = -1.5 in the folder: undo it so that the capture lines up with the phone
    truth = type(truth)(**{**truth.__dict__, "t_s": t})
    est, info = estimate_mount_rotation(rec, truth)
    assert np.degrees(Rotation.from_matrix(est @ r_mount.T).magnitude()) < 1.0
    assert info["rate_rms_residual_rads"] < 0.1 * info["rate_rms_rads"]


def test_data_set_root_listing_and_manifest(tmp_path):
    android_folder(tmp_path)
    android_folder(tmp_path, "Alice_Nexus5_Dist_Swinging_old")
    ios_folder(tmp_path)
    (tmp_path / "android" / "calib_acc_Nexus5_d1").mkdir()
    assert detect_format(tmp_path) == "tyrex-set"
    assert len(list_dataset(tmp_path)) == 3 == len(list_tyrex_folders(tmp_path))
    recs = read_dataset(tmp_path)
    assert sorted(r.meta["subject"] for r in recs) == ["Alice", "Alice", "Bob"]
    man = tyrex_manifest(tmp_path)
    assert list(man["motion"]) == ["Swinging", "Texting", "BackPocket"]
    assert list(man["take"]) == ["old", "", ""]
    assert set(man["platform"]) == {"android", "ios"}


def test_truncated_log_is_one_line_error(tmp_path):
    d = android_folder(tmp_path)
    with gzip.open(d / "gyroscope-calibrated.txt.gz", "at") as fh:
        fh.write("31.0 0.1 0.2\n")
    with pytest.raises(InputError, match="has 4 columns|non-numeric value at row"):
        read_tyrex(d)


# ------------------------------------------------------------------ the real data set


@pytest.mark.realdata
@pytest.mark.parametrize(
    "name",
    ["android/Guillaume_Nexus5_NoDist_Texting", "ios/Jakob_iPhone4S_NoDist_Backpocket", "ios/Thibaud_iPhone5_NoDist_AR"],
)
def test_real_counts_rates_and_gravity(name):
    from tests.conftest import shared

    d = shared("tyrex-attitude", name)
    raw_acc = np.loadtxt(d / "accelerometer.txt.gz")
    gyr_file = "gyroscope-calibrated.txt.gz" if name.startswith("android") else "gyroscope.txt.gz"
    raw_gyr = np.loadtxt(d / gyr_file)
    rec = read_tyrex(d)
    assert rec.meta["n_acc_samples"] == len(raw_acc) and rec.meta["n_gyr_samples"] == len(raw_gyr)
    assert rec.sampling_rate_hz == pytest.approx(1 / np.median(np.diff(raw_acc[:, 0])), rel=1e-3)
    # the recording spans every accelerometer sample (the clock merge keeps them all)
    t_acc = raw_acc[:, 0]
    assert (rec.n_samples - 1) / rec.sampling_rate_hz == pytest.approx(t_acc[-1] - t_acc[0], abs=1.5 / rec.sampling_rate_hz)
    # |acc| near g where the gyroscope is still (the phone at rest in any position), in m/s^2 on both platforms
    k = int(0.5 * rec.sampling_rate_hz)
    still = np.convolve(np.linalg.norm(rec.gyr, axis=1), np.ones(k) / k, mode="same") < 0.15
    mag = np.linalg.norm(rec.acc, axis=1)
    assert still.sum() > k  # these recordings hold the phone still at times
    assert np.median(mag[still]) == pytest.approx(G, abs=0.3)


@pytest.mark.realdata
@pytest.mark.parametrize("name", ["android/Jakob_Nexus5_NoDist_Swinging", "ios/Guillaume_iPhone5_NoDist_FrontPocket"])
def test_real_time_alignment_and_mount(name):
    """|acc| against the motion capture's |second derivative + g| correlates best near lag 0 on the phone's clock."""
    from tests.conftest import shared

    d = shared("tyrex-attitude", name)
    rec = read_tyrex(d)
    truth = read_tyrex_truth(d)
    fs = 60.0
    t = np.arange(truth.t_s[0] + 1, truth.t_s[-1] - 1, 1 / fs)
    pos = truth.position_at(t)
    ok = np.isfinite(pos).all(axis=1)
    pos = np.column_stack([np.interp(t, t[ok], pos[ok, j]) for j in range(3)])
    # positions at 0.1 mm: smooth before differencing twice
    box = np.ones(5) / 5
    pos = np.column_stack([np.convolve(pos[:, j], box, mode="same") for j in range(3)])
    accel = np.gradient(np.gradient(pos, 1 / fs, axis=0), 1 / fs, axis=0)
    accel[:, 2] += G
    mocap = np.linalg.norm(accel, axis=1)[5:-5]
    tp = truth.recording_times(rec)
    mag = np.interp(t, tp, np.convolve(np.linalg.norm(rec.acc, axis=1), np.ones(5) / 5, mode="same"))[5:-5]
    lags = np.arange(-30, 31)  # +-0.5 s
    corr = [np.corrcoef(np.roll(mag, lag)[40:-40], mocap[40:-40])[0, 1] for lag in lags]
    best = lags[int(np.argmax(corr))] / fs
    assert abs(best) <= 0.05 and max(corr) > 0.5
    r_mount, info = estimate_mount_rotation(rec, truth)
    # the holder is fixed to the phone with its axes along the phone's: a rotation of a few degrees
    assert info["angle_from_identity_deg"] < 10.0
    assert info["rate_rms_residual_rads"] < 0.4 * info["rate_rms_rads"]


@pytest.mark.realdata
def test_real_manifest_lists_every_recording():
    from tests.conftest import shared

    root = shared("tyrex-attitude")
    man = tyrex_manifest(root)
    assert len(man) == 127  # 126 + the extra take without motion capture
    assert (man["truth"] == "").sum() == 1
    assert man.groupby("subject").size().to_dict() == {"Guillaume": 42, "Jakob": 43, "Thibaud": 42}
    assert (man["mode"] == "run").sum() == 18


@pytest.mark.parametrize("command", ["info", "split"])
def test_unit_flags_are_refused_for_a_tyrex_folder(tmp_path, capsys, command):
    """The tyrex units are documented (m/s^2, or g converted by the reader): --acc-unit would change nothing."""
    from gaitml.cli import main

    d = android_folder(tmp_path)
    argv = [command, str(d), "--acc-unit", "g"] + (["--out", str(tmp_path / "segs")] if command == "split" else [])
    assert main(argv) == 2
    assert "drop --acc-unit" in capsys.readouterr().err
    assert not (tmp_path / "segs").exists()
