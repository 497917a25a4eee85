"""experiments.scripts.run_dynamics: the gyroscope-top count, the motion-capture speed, the dynamics z and the fold lookup."""

from __future__ import annotations

import gzip
from types import SimpleNamespace

import numpy as np
import pytest

from experiments.scripts import run_dynamics as rd
from experiments.tests.mocap_fakes import FS, circle_walk, fake_truth


def _gyro_file(path, gyr, fs=100.0):
    t = np.arange(len(gyr)) / fs
    with gzip.open(path, "wt") as fh:
        np.savetxt(fh, np.column_stack([t, gyr]))
    return path


def test_a_gyroscope_at_its_range_shows_a_flat_top_and_a_free_one_does_not(tmp_path):
    t = np.arange(2000) / 100.0
    swing = 3.0 + 3.0 * np.random.default_rng(5).random(28)  # every swing its own amplitude (3-6 rad/s), as a run's are
    free = np.column_stack([swing[(1.4 * t).astype(int)] * np.sin(2 * np.pi * 1.4 * t), 0.5 * np.cos(t), 0.1 * t])
    clipped = free.copy()
    clipped[:, 0] = np.clip(clipped[:, 0], -4.0, 4.0)  # a range of 4 rad/s: every swing past it reads 4
    top_free = rd.gyro_top(_gyro_file(tmp_path / "free.txt.gz", free))
    top_clip = rd.gyro_top(_gyro_file(tmp_path / "clip.txt.gz", clipped))
    assert top_free["gyr_max_rad_s"] == pytest.approx(swing.max(), rel=1e-3)
    assert top_free["gyr_max_dps"] == pytest.approx(np.degrees(top_free["gyr_max_rad_s"]))
    assert top_free["share_at_top"] < 0.01  # only the crests of the largest swings come near the top
    assert top_free["share_at_top"] == pytest.approx(top_free["samples_at_top"] / len(free))
    assert top_clip["gyr_max_rad_s"] == pytest.approx(4.0)
    assert top_clip["share_at_top"] > 0.1  # every swing past the range sits at it


def test_the_window_speed_follows_the_body_not_the_sway():
    t, pos, rot, _ = circle_walk(seconds=60.0, speed=1.8)
    pos = pos.copy()
    pos[:, 1] += 0.15 * np.sin(2 * np.pi * 1.4 * t)  # an arm swing across the path at the stride rate
    truth = fake_truth(t, pos, rot)
    rec = SimpleNamespace(t_s=np.arange(0, 50.0, 1 / 50.0) + 2.0, sampling_rate_hz=50.0, meta={"t0_original_s": 0.0})
    starts = np.arange(0, 2200, 100)
    v = rd.window_speed(rec, truth, starts, 256)
    assert np.isfinite(v).all()
    assert np.allclose(v, 1.8, rtol=0.03)
    raw = np.hypot(*np.diff(pos[:, :2], axis=0).T).sum() / (t[-1] - t[0])
    assert raw > 1.8 * 1.05  # the unsmoothed phone path would overstate it
    late = rd.window_speed(rec, truth, np.array([2990]), 256)  # past the motion capture: not measured
    assert np.isnan(late).all()
    assert FS == 60.0


def test_dynamics_z_is_the_standardised_gap_to_the_nearest_gaussian():
    q = 13
    center, scale = np.linspace(0, 1, q), np.full(q, 2.0)
    means = np.stack([np.zeros(q), np.full(q, 5.0)])
    cov = np.diag(np.full(q, 4.0))
    precs = np.stack([np.linalg.inv(cov), np.linalg.inv(cov)])
    dom = SimpleNamespace(arrays={"dyn_center": center, "dyn_scale": scale, "dyn_means": means, "dyn_precisions": precs})
    Q = np.stack([center + scale * 1.0, center + scale * 6.0])  # standardised 1 (near Gaussian 0) and 6 (near 1)
    k, d, z = rd.dynamics_z(dom, Q)
    assert list(k) == [0, 1]
    assert np.allclose(z[0], 0.5) and np.allclose(z[1], 0.5)  # (1 - 0) / 2 and (6 - 5) / 2
    assert np.allclose(d, np.sqrt(q * 0.25))


def test_resolve_fold_reads_both_cache_layouts_and_says_what_is_missing(tmp_path):
    a = tmp_path / "a" / "a-Jakob"
    a.mkdir(parents=True)
    (a / "model.json").write_text("{}")
    assert rd.resolve_fold(tmp_path / "a", "a", "Jakob") == a
    b = tmp_path / "b" / "models" / "demo-a-Jakob-0123456789ab"
    b.mkdir(parents=True)
    (b / "model.json").write_text("{}")
    assert rd.resolve_fold(tmp_path / "b", "a", "Jakob") == b
    with pytest.raises(SystemExit, match="found 0"):
        rd.resolve_fold(tmp_path / "b", "a", "Thibaud")


def test_the_raw_gyroscope_files_of_both_phone_kinds_are_read_in_rad_per_s():
    from experiments.tests.conftest import shared

    data = shared("tyrex-attitude").parent
    for name in ("Jakob_Nexus5_NoDist_RunningHand", "Jakob_iPhone5_NoDist_RunningHand"):
        path = rd.raw_gyro_file(data, name)
        with gzip.open(path, "rt") as fh:
            g = np.loadtxt(fh)[:, 1:4]
        top = rd.gyro_top(path)
        assert top["gyr_max_rad_s"] == pytest.approx(np.abs(g).max())
        assert 1.0 < top["gyr_max_rad_s"] < 50.0  # a running hand turns at rad/s, not deg/s nor mrad/s
        assert top["samples_at_top"] >= 1
    with pytest.raises(FileNotFoundError, match="no gyroscope file"):
        rd.raw_gyro_file(data, "Nobody_Nexus5_NoDist_RunningHand")


def test_all_gyro_tops_gives_one_row_per_phone_with_its_largest_recording(tmp_path):
    t = np.arange(1000) / 100.0
    for sub, name, fname, amp in (
        ("android", "A_Nexus5_NoDist_Swinging", "gyroscope-calibrated.txt.gz", 3.0),
        ("android", "B_Nexus5_NoDist_RunningHand", "gyroscope-calibrated.txt.gz", 7.0),
        ("android", "calib_gyr_Nexus5_d1", "gyroscope-calibrated.txt.gz", 50.0),
        ("ios", "A_iPhone5_NoDist_Texting", "gyroscope.txt.gz", 2.0),
    ):
        d = tmp_path / "tyrex-attitude" / sub / name
        d.mkdir(parents=True)
        g = np.column_stack([amp * np.sin(2 * np.pi * 1.3 * t + 0.1), np.zeros_like(t), np.zeros_like(t)])
        _gyro_file(d / fname, g)
    tab = rd.all_gyro_tops(tmp_path).set_index("phone")
    assert set(tab.index) == {"Nexus5", "iPhone5"}
    assert tab.loc["Nexus5", "recordings"] == 2  # the calibration folder is not a recording
    assert tab.loc["Nexus5", "in"] == "B_Nexus5_NoDist_RunningHand"
    assert tab.loc["Nexus5", "largest abs gyro (rad/s)"] == pytest.approx(7.0, rel=1e-3)
