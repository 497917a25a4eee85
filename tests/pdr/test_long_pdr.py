"""`gaitml pdr` on a long file: chunk by chunk in bounded memory, the same answer as a whole-file run (issue 28).

Tolerance from the physics: the chunked run carries the attitude quaternion exactly across
chunks; only the complementary filter's gravity low-pass is recomputed per chunk, which
moves a step's heading by far less than 1e-4 rad (0.006 deg). Over a 0.7 m step that is
under 0.1 mm sideways, so over the 240 s walks below (~300 steps) the positions must agree
within 1 mm per step summed, and we ask for 1 mm in total; the steps must be identical.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import gaitml.chunked_run as cr
import gaitml.io.chunked as ch
from gaitml.chunked_run import long_pdr
from gaitml.cli import main
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.pdr import run_pdr
from gaitml.pdr.attitude import AttitudeEstimator
from gaitml.simulate import simulate_dataset

HEADING_TOL_RAD = 1e-4
POSITION_TOL_M = 1e-3


@pytest.fixture(scope="module")
def walk_file(tmp_path_factory):
    rec = simulate_dataset(1, 240.0, sampling_rate_hz=50.0, seed=3)[0]
    p = tmp_path_factory.mktemp("longpdr") / "walk.csv"
    write_gaitml_csv(rec, p)
    return p


def _compare(whole, chunked):
    np.testing.assert_array_equal(chunked.steps["peak"].to_numpy(), whole.steps["peak"].to_numpy())
    dh = np.angle(np.exp(1j * (chunked.steps["gyro_heading_rad"].to_numpy() - whole.steps["gyro_heading_rad"].to_numpy())))
    assert np.abs(dh).max() < HEADING_TOL_RAD
    dxy = chunked.trajectory[["x_m", "y_m"]].to_numpy() - whole.trajectory[["x_m", "y_m"]].to_numpy()
    assert np.hypot(dxy[:, 0], dxy[:, 1]).max() < POSITION_TOL_M
    assert list(chunked.trajectory["mode"]) == list(whole.trajectory["mode"])
    assert chunked.distance_m == pytest.approx(whole.distance_m, rel=1e-9)


@pytest.mark.parametrize("heading", ["hde", "gyro"])
@pytest.mark.parametrize("modes", ["forward", "true"])
def test_long_pdr_equals_whole_file(walk_file, heading, modes, monkeypatch):
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 1234)  # read blocks that are not chunk boundaries
    # single-peak: a detector whose state is local, so the 5 s margins of this test suffice (the adaptive
    # default learns its thresholds again in every chunk's margin, 30 s by default)
    whole = run_pdr(read_recording(walk_file), heading=heading, modes=modes, detector="single-peak")
    chunked = long_pdr(walk_file, heading=heading, modes=modes, chunk_s=30.0, margin_s=5.0, progress=False, detector="single-peak")
    assert whole.n_steps > 250
    _compare(whole, chunked)
    assert set(chunked.info) == set(whole.info)


def test_long_pdr_with_a_model_equals_whole_file(walk_file):
    from gaitml.models import load_model
    from tests.conftest import ROOT

    model = load_model(ROOT / "models" / "demo")
    for short in (0.0, 1.0):  # the short-run rule off and on reads the whole step sequence in both
        kw = {"model": model, "modes": "model", "mode_boundaries": "nearest", "detector": "single-peak", "short_run_windows": short}
        whole = run_pdr(read_recording(walk_file), **kw)
        chunked = long_pdr(walk_file, **kw, chunk_s=30.0, margin_s=5.0, progress=False)
        _compare(whole, chunked)
        assert list(chunked.steps["in_domain"]) == list(whole.steps["in_domain"])
        assert chunked.info["short_run_steps"] == whole.info["short_run_steps"]


def test_attitude_continued_from_a_carried_state_is_the_whole_integration():
    """The attitude filter's state is the quaternion and the gyroscope bias: continuing from sample k gives the same attitudes."""
    rec = simulate_dataset(1, 60.0, sampling_rate_hz=50.0, seed=5)[0]
    whole = AttitudeEstimator().estimate(rec)
    k = 1234
    cont = AttitudeEstimator().estimate_from(rec, k, whole.rotation_[k], initial_bias_rads=whole.bias_rads_[k])
    assert np.allclose(cont.bias_rads_, whole.bias_rads_[k:], atol=1e-12)
    d = np.angle(np.exp(1j * (cont.heading_rad_ - whole.heading_rad_[k:])))
    assert np.abs(d).max() < 1e-9


def test_drift_rate_score_in_blocks_is_the_whole_score(monkeypatch):
    """The drift-rate fit sums its score over blocks of steps (bounded memory); the fitted rate is the same."""
    import gaitml.pdr.hde as hde

    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.45, 0.6, 3000))
    psi = np.repeat(rng.choice(np.arange(12) * np.pi / 6, 30), 100) + 0.004 * t + rng.normal(0, 0.05, 3000)
    blocked = hde.estimate_drift_rate(psi, t)
    monkeypatch.setattr(hde, "_SCORE_BLOCK", 10**9)
    assert blocked == pytest.approx(hde.estimate_drift_rate(psi, t), abs=1e-12)
    assert blocked == pytest.approx(0.004, abs=5e-4)


def _force_long(monkeypatch):
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 999)
    monkeypatch.setattr(cr, "DEFAULT_CHUNK_S", 30.0)
    monkeypatch.setattr(cr, "DEFAULT_MARGIN_S", 5.0)


def test_pdr_cli_long_path_equals_whole(walk_file, monkeypatch, capsys, tmp_path):
    import pandas as pd

    short = tmp_path / "short.csv"
    assert main(["pdr", str(walk_file), "--json", "--out", str(short)]) == 0
    a = json.loads(capsys.readouterr().out)
    _force_long(monkeypatch)

    def no_whole_read(*_a, **_k):  # the chunked path must never read the file whole
        raise AssertionError("pdr read a long input whole")

    monkeypatch.setattr("gaitml.commands.pdr.load_input", no_whole_read)
    long = tmp_path / "long.csv"
    plot = tmp_path / "long.png"
    assert main(["pdr", str(walk_file), "--json", "--out", str(long), "--plot", str(plot)]) == 0
    cap = capsys.readouterr()
    b = json.loads(cap.out)
    assert "read in chunks" in cap.err and plot.stat().st_size > 0
    assert set(b) == set(a) and b["n_steps"] == a["n_steps"]
    assert np.abs(np.subtract(b["end_xy_m"], a["end_xy_m"])).max() < POSITION_TOL_M
    ta, tb = pd.read_csv(short), pd.read_csv(long)
    assert list(ta.columns) == list(tb.columns) and len(ta) == len(tb)
    assert np.abs(tb[["x_m", "y_m"]].to_numpy() - ta[["x_m", "y_m"]].to_numpy()).max() < POSITION_TOL_M


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--truth", "self"], "--truth"),
        (["--heading", "dwpca"], "dwpca heading"),
        (["--heading", "dwpca-hde"], "dwpca-hde heading"),
        (["--model", "MODEL", "--mode-boundaries", "refine"], "--mode-boundaries refine"),
    ],
)
def test_pdr_cli_long_path_refusals(walk_file, monkeypatch, capsys, tmp_path, extra, needle):
    from tests.conftest import ROOT

    _force_long(monkeypatch)

    def no_read(*_a, **_k):  # refused before the first pass over the file
        raise AssertionError("pdr read the input before refusing an option")

    monkeypatch.setattr("gaitml.commands.pdr.long_read_kwargs", no_read)
    out = tmp_path / "traj.csv"
    argv = ["pdr", str(walk_file), "--out", str(out), *[str(ROOT / "models" / "demo") if a == "MODEL" else a for a in extra]]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0] and "chunks" in err[0]
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_pdr_cli_long_path_summary_is_the_whole_files(walk_file, monkeypatch, capsys, tmp_path):
    """With a reference trajectory sidecar, both roads start from its heading and print the same summary
    (steps, distance, end point, HDE's heading check, the end-point error line)."""
    import shutil

    import pandas as pd

    f = tmp_path / "walk.csv"
    shutil.copy(walk_file, f)
    pd.DataFrame({"t_s": [0.0, 100.0, 200.0], "x_m": [0.0, 30.0, 60.0], "y_m": [0.0, 90.0, 180.0], "heading_rad": 0.3}).to_csv(
        tmp_path / "walk.trajectory.csv", index=False
    )
    assert main(["pdr", str(f)]) == 0
    short = capsys.readouterr()
    _force_long(monkeypatch)
    assert main(["pdr", str(f)]) == 0
    long = capsys.readouterr()
    assert "start heading 0.300 rad" in long.err and "start heading 0.300 rad" in short.err
    lines = long.out.strip().splitlines()
    assert len(lines) == 4 and lines[1].startswith("  gyroscope bias") and lines[3].startswith("  truth:")
    assert lines[2].startswith("  heading check: HDE applied")  # HDE's structure guard, on the whole file's steps
    assert lines == short.out.strip().splitlines()


@pytest.fixture(scope="module")
def biased_file(tmp_path_factory):
    """60 s of walking, 10 s still, 20 s of walking; a gyroscope bias (0.04, -0.03, 0.05) rad/s throughout.
    The still stretch lies after the first 30 s chunk, so a bias found on the first chunk alone would be wrong."""
    from gaitml.consts import GRAVITY_MS2
    from gaitml.recording import Recording

    fs = 50.0
    a = simulate_dataset(1, 60.0, sampling_rate_hz=fs, seed=3, modes=("walk",))[0]
    b = simulate_dataset(1, 20.0, sampling_rate_hz=fs, seed=4, modes=("walk",))[0]
    rng = np.random.default_rng(0)
    n = int(10 * fs)
    up = a.acc[-int(fs) :].mean(axis=0)
    acc_still = up / np.linalg.norm(up) * GRAVITY_MS2 + rng.normal(0, 0.02, (n, 3))
    gyr_still = rng.normal(0, 0.003, (n, 3))
    acc = np.vstack([a.acc, acc_still, b.acc])
    gyr = np.vstack([a.gyr, gyr_still, b.gyr]) + np.array([0.04, -0.03, 0.05])
    p = tmp_path_factory.mktemp("longpdr_bias") / "biased.csv"
    write_gaitml_csv(Recording.from_arrays(acc, fs, gyr=gyr), p)
    return p


@pytest.mark.parametrize("gyro_bias", ["still", "auto"])
def test_long_pdr_takes_the_gyro_bias_of_the_whole_file(biased_file, gyro_bias):
    """The bias comes from the still stretches of the whole file, not of the first chunk: the trajectory and the
    reported bias are the whole-file run's (a first-chunk bias left 45 m between them on this file)."""
    kw = {"modes": "forward", "detector": "single-peak", "gyro_bias": gyro_bias}
    whole = run_pdr(read_recording(biased_file), **kw)
    chunked = long_pdr(biased_file, **kw, chunk_s=30.0, margin_s=5.0, progress=False)
    assert whole.info["gyro_bias"]["method"] in ("still", "still+online")
    _compare(whole, chunked)
    a, b = whole.info["gyro_bias"], chunked.info["gyro_bias"]
    assert b["method"] == a["method"] and b["n_still_windows"] == a["n_still_windows"]
    assert b["still_s"] == pytest.approx(a["still_s"], abs=1e-9)
    np.testing.assert_allclose(b["bias_rads"], a["bias_rads"], atol=1e-6)
    assert chunked.to_json_dict()["gyro_bias"]["bias_rads"] == b["bias_rads"]


def test_still_windows_of_the_chunks_give_the_whole_file_bias(biased_file):
    """gyro_bias_from_windows over the windows of every chunk's core is estimate_gyro_bias of the whole recording."""
    from gaitml.chunked_run import long_still_bias
    from gaitml.signal import estimate_gyro_bias, gyro_bias_from_windows, gyro_still_windows

    rec = read_recording(biased_file)
    whole = estimate_gyro_bias(rec.acc, rec.gyr, rec.sampling_rate_hz)
    assert whole.method == "still" and whole.still_s >= 8.0
    chunked = long_still_bias(biased_file, chunk_s=7.3, progress=False)
    assert chunked.n_still_windows == whole.n_still_windows
    assert chunked.still_s == pytest.approx(whole.still_s, abs=1e-9)
    np.testing.assert_allclose(chunked.bias_rads, whole.bias_rads, atol=1e-9)
    np.testing.assert_allclose(chunked.bias_rads, [0.04, -0.03, 0.05], atol=0.005)
    # parts cut anywhere (not on the window grid), each holding its windows whole: the same windows
    cut = [0, 777, 2001, rec.n_samples]
    parts = [
        gyro_still_windows(rec.acc[lo : hi + 60], rec.gyr[lo : hi + 60], rec.sampling_rate_hz, offset=lo).select(lo, hi)
        for lo, hi in zip(cut[:-1], cut[1:], strict=True)
    ]
    assert gyro_bias_from_windows(parts).bias_rads == pytest.approx(whole.bias_rads, abs=1e-9)


def test_pdr_cli_long_path_reports_the_whole_file_bias(biased_file, monkeypatch, capsys):
    argv = ["pdr", str(biased_file), "--json", "--gyro-bias", "still", "--modes", "forward", "--detector", "single-peak"]
    assert main(argv) == 0
    a = json.loads(capsys.readouterr().out)
    _force_long(monkeypatch)
    assert main(argv) == 0
    b = json.loads(capsys.readouterr().out)
    assert b["gyro_bias"]["method"] == a["gyro_bias"]["method"] == "still"
    np.testing.assert_allclose(b["gyro_bias"]["bias_rads"], a["gyro_bias"]["bias_rads"], atol=1e-6)
    assert b["n_steps"] == a["n_steps"]
    assert np.abs(np.subtract(b["end_xy_m"], a["end_xy_m"])).max() < POSITION_TOL_M
