"""The tyrex motion capture put on the phone's clock: timeAlignment.txt as it is, and refined from the sensors."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.errors import InputError
from gaitml.io.tyrex import ALIGN_GRID_HZ, read_tyrex, read_tyrex_truth, refine_tyrex_alignment
from gaitml.recording import Recording

G = 9.80665
DURATION_S = 40.0
#: The mount: body axes = R phone axes (a few degrees, as on the real set)
R_MOUNT = Rotation.from_euler("xyz", [4.0, -3.0, 10.0], degrees=True).as_matrix()


def _attitude(t: np.ndarray) -> Rotation:
    """A gait-like attitude of the capture's body (body to room) that does not repeat: a stride swing whose
    amplitude and tempo wander, and two turns."""
    t = np.asarray(t, dtype=float)
    amp = 0.3 * (1.0 + 0.6 * np.sin(2 * np.pi * t / 13.0) + 0.3 * np.sin(2 * np.pi * t / 7.3))
    phase = 2 * np.pi * (0.9 * t + 0.8 * np.sin(2 * np.pi * t / 17.0))
    yaw = 1.6 * (np.tanh((t - 12.0) / 0.8) - np.tanh((t - 27.0) / 1.1))
    swing = Rotation.from_rotvec(np.column_stack([amp * np.sin(phase), 0.3 * amp * np.cos(2 * phase), np.zeros_like(t)]))
    return Rotation.from_euler("z", yaw[:, None]) * swing


def _bounce(t: np.ndarray) -> np.ndarray:
    """Positions (m) of the phone: a walk forward with a step bounce whose height wanders and a stop at 17-22 s
    (room frame, z up)."""
    t = np.asarray(t, dtype=float)
    stop = 1.0 - np.exp(-(((t - 19.5) / 2.5) ** 6))
    h = 0.03 * (1.0 + 0.7 * np.sin(2 * np.pi * t / 11.0)) * stop
    return np.column_stack(
        [1.2 * t, 0.3 * np.sin(2 * np.pi * t / 19.0), 1.0 + h * np.sin(2 * np.pi * (1.8 * t + 3.0 * np.sin(2 * np.pi * t / 9.0)))]
    )


def _log(path: Path, t: np.ndarray, x: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(path, "wt") as fh:
        for ti, row in zip(t, x, strict=True):
            fh.write(f"{ti:.9f} {row[0]:.7g} {row[1]:.7g} {row[2]:.7g}\n")


def _folder(root: Path, *, dt_true: float, dt_file: float, still: bool = False, name: str = "Alice_Nexus5_NoDist_Swinging") -> Path:
    """An Android recording whose capture's clock is ``phone + dt_true`` while ``timeAlignment.txt`` says ``dt_file``.

    The capture's attitude is the phone's rotated by the mount, integrated from the same angular rate; its
    positions are :func:`_bounce`; the accelerometer is the specific force of those positions in the phone's axes.
    ``still``: the phone lies still (only sensor noise).
    """
    rng = np.random.default_rng(7)
    d = root / "android" / name
    fs = 199.0
    t = 0.3 + np.arange(int(DURATION_S * fs)) / fs
    fine = np.arange(0.0, DURATION_S + 1.0, 1 / 1200)
    body = _attitude(0.0 * fine if still else fine)
    # the body's rate in its own axes between fine samples, and the phone's (gyroscope) through the mount
    w_body = (body[:-1].inv() * body[1:]).as_rotvec() * 1200
    w = np.vstack([w_body, w_body[-1:]]) @ R_MOUNT
    pos = np.zeros((len(fine), 3)) + [0.0, 0.0, 1.0] if still else _bounce(fine)
    vel = np.gradient(pos, fine, axis=0)
    f_room = np.gradient(vel, fine, axis=0) + [0.0, 0.0, G]
    # the phone's specific force: room -> body -> phone axes
    f_phone = body.inv().apply(f_room) @ R_MOUNT
    idx = np.clip(np.searchsorted(fine, t), 0, len(fine) - 1)
    noise = rng.normal(0, 0.01, (len(t), 3))
    _log(d / "accelerometer.txt.gz", t, f_phone[idx] + 5 * noise)
    _log(d / "gyroscope-calibrated.txt.gz", t + 0.0021, w[idx] + noise)
    (d / "record.properties").write_text("[Device]\nModel = Nexus 5\n")
    (d / "timeAlignment.txt").write_text(f"  {dt_file:.7e}\n")
    # the capture: 60 Hz frames at phone times tp, stamped tp + dt_true on its own clock
    tp = np.arange(0.0, DURATION_S + 0.5, 1 / 60)
    k = np.clip(np.searchsorted(fine, tp), 0, len(fine) - 1)
    dcm = np.transpose(body[k].as_matrix(), (0, 2, 1))  # QTM's DCM: room to body
    f = root / "qualisys" / f"{name}.csv.gz"
    f.parent.mkdir(parents=True, exist_ok=True)
    lines = ["# frame_rate_hz=60", "t_s,x_mm,y_mm,z_mm," + ",".join(f"rot{i}" for i in range(9)) + ",residual_mm"]
    for j, tj in enumerate(tp):
        vals = [*(1000 * pos[k[j]]), *dcm[j].reshape(9)]
        lines.append(f"{tj + dt_true:.5f}," + ",".join(f"{v:.6f}" for v in vals) + ",0.5")
    with gzip.open(f, "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    return d


@pytest.mark.parametrize("error_s", [-0.45, 0.3])
def test_refine_recovers_a_known_lag_and_file_keeps_the_file(tmp_path, error_s):
    """The file's dt is off by ``error_s``: 'refine' finds the capture's true dt within one grid step, 'file' keeps
    the file's dt exactly."""
    dt_true = -2.0
    d = _folder(tmp_path, dt_true=dt_true, dt_file=dt_true + error_s)
    file = read_tyrex_truth(d, align="file")
    assert file.dt_s == file.dt_file_s == pytest.approx(dt_true + error_s)
    assert file.align == {"mode": "file"}
    ref = read_tyrex_truth(d)  # the default
    assert ref.align["mode"] == "refine" and ref.align["accepted"] and ref.align["signal"] == "gyro"
    assert ref.dt_file_s == pytest.approx(dt_true + error_s)
    assert abs(ref.dt_s - dt_true) <= 1 / ALIGN_GRID_HZ
    # the capture moves by the correction, nothing else changes
    np.testing.assert_allclose(ref.t_s, file.t_s + (file.dt_s - ref.dt_s))
    np.testing.assert_array_equal(ref.pos_m, file.pos_m)
    assert ref.align["corr_peak"] >= 0.8 and ref.align["corr_peak"] > ref.align["corr_file"]
    assert "refined" in ref.align_note and f"{dt_true + error_s:+.3f}" in ref.align_note
    # the same from a recording passed in (here at a lower rate, as the pipeline holds it)
    from gaitml.models import resample_recording

    rec = resample_recording(read_tyrex(d), 50.0)
    via = read_tyrex_truth(d, recording=rec)
    assert abs(via.dt_s - dt_true) <= 1 / ALIGN_GRID_HZ


def test_without_a_gyroscope_the_accelerometer_aligns(tmp_path):
    dt_true = 1.0
    d = _folder(tmp_path, dt_true=dt_true, dt_file=dt_true - 0.35)
    rec = read_tyrex(d)
    no_gyr = Recording.from_timestamps(rec.meta["t0_original_s"] + rec.t_s, rec.acc, meta={"source": str(d)})
    assert no_gyr.gyr is None
    truth = read_tyrex_truth(d, recording=no_gyr)
    assert truth.align["signal"] == "acc" and truth.align["accepted"], truth.align
    assert abs(truth.dt_s - dt_true) <= 1 / ALIGN_GRID_HZ


def test_a_still_recording_keeps_the_files_dt_and_says_so(tmp_path):
    d = _folder(tmp_path, dt_true=0.5, dt_file=0.2, still=True)
    truth = read_tyrex_truth(d)
    assert not truth.align["accepted"] and truth.align["reason"]
    assert truth.dt_s == truth.dt_file_s == pytest.approx(0.2)
    assert "kept" in truth.align_note and "not refined" in truth.align_note


def test_the_dense_truth_notes_say_how_the_capture_was_aligned(tmp_path):
    from gaitml.io.truth import tyrex_truth

    d = _folder(tmp_path, dt_true=-2.0, dt_file=-2.4)
    tr = tyrex_truth(read_tyrex(d))
    assert any("refined by" in n and "-2.400" in n for n in tr.notes), tr.notes


@pytest.mark.parametrize("align", ["Refine", "auto", ""])
def test_an_unknown_align_is_a_one_line_error(tmp_path, align):
    d = _folder(tmp_path, dt_true=0.0, dt_file=0.0, still=True)
    with pytest.raises(InputError, match="is not a tyrex alignment; use one of 'refine', 'file'") as exc:
        read_tyrex_truth(d, align=align)
    assert "\n" not in str(exc.value)


def test_refine_alignment_refuses_an_unknown_signal(tmp_path):
    d = _folder(tmp_path, dt_true=0.0, dt_file=0.0, still=True)
    truth = read_tyrex_truth(d, align="file")
    with pytest.raises(InputError, match="not an alignment signal"):
        refine_tyrex_alignment(truth, np.zeros(3), np.zeros((3, 3)), None, None, signal="mag")


@pytest.mark.realdata
@pytest.mark.parametrize("name", ["android/Guillaume_Nexus5_NoDist_FrontPocket", "android/Jakob_Nexus5_NoDist_RunningPocket"])
def test_real_nexus5_captures_are_on_the_phone_clock_within_a_few_frames(name):
    """The file's dt is right to within a few capture frames on the Nexus 5 too: the 0.1-0.6 s 'lag' seen on these
    recordings was the phone's first sample time (``t0_original_s``) dropped from the phone's clock."""
    from gaitml.io.tyrex import tyrex_phone_logs
    from tests.conftest import shared

    d = shared("tyrex-attitude", name)
    truth = read_tyrex_truth(d)
    assert truth.align["accepted"] and truth.align["corr_peak"] >= 0.9
    assert abs(truth.dt_s - truth.dt_file_s) < 0.05
    t_acc, acc, t_gyr, gyr = tyrex_phone_logs(d)
    assert t_acc[0] > 0.1  # the Nexus 5 logs start a while after the recording's start
    lost = refine_tyrex_alignment(read_tyrex_truth(d, align="file"), t_acc - t_acc[0], acc, t_gyr - t_acc[0], gyr)
    assert lost["shift_s"] == pytest.approx(truth.align["shift_s"] - t_acc[0], abs=0.02)
