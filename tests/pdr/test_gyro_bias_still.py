"""A gyroscope bias from a separate still recording of the same phone (``gaitml pdr --gyro-bias-from STILL``).

A phone's gyroscope bias about the vertical is not observable while it walks (nothing in
gravity measures it), so the walk's own estimate leaves it and the heading drifts by
bias x time. A recording of the same phone lying still measures it (the static bias test).
These tests walk a simulated phone with a known constant bias and check that the bias of
its still recording removes the drift, whole and chunked, and that a bad STILL is refused
with one line and no output.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import gaitml.io.chunked as ch
from gaitml.chunked_run import long_pdr
from gaitml.cli import main
from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.pdr import run_pdr
from gaitml.recording import Recording
from gaitml.signal import gyro_bias_from_still, read_gyro_bias_json
from tests.pdr.synth import FS, synth_walk

#: the phone's bias (rad/s): 0.03 rad/s about the vertical is 103 deg/min of heading drift, of the order
#: of the raw iPhone gyroscopes of the tyrex benchmark (0.10 rad/s on one axis)
BIAS = (0.01, -0.02, 0.03)
LEGS = [("walk", 50, np.pi / 2), ("walk", 50, -np.pi / 2), ("walk", 50, 0.0)]
#: heading left after removing the still recording's bias: its mean over 30 s of noise 0.003 rad/s is
#: good to ~1e-4 rad/s, 0.5 deg over the 90 s walk; the gravity correction of the tilt adds a little
HEADING_TOL_DEG = 2.0


def _still(seconds: float, bias=BIAS, *, fs: float = FS, seed: int = 5, gyr=True) -> Recording:
    """The phone lying flat and untouched: gravity on z, the gyroscope reads its bias plus noise."""
    rng = np.random.default_rng(seed)
    n = int(seconds * fs)
    acc = np.tile([0.0, 0.0, GRAVITY_MS2], (n, 1)) + rng.normal(0, 0.02, (n, 3))
    g = np.asarray(bias, dtype=float) + rng.normal(0, 0.003, (n, 3))
    return Recording.from_arrays(acc, fs, gyr=g if gyr else None, meta={"id": "still"})


@pytest.fixture(scope="module")
def walks():
    # half a second still at each end: too little for the walk's own still-stretch estimate (2 s)
    biased = synth_walk(LEGS, gyro_bias_rads=BIAS, noise=0.05, seed=2, pause_s=0.5)
    clean = synth_walk(LEGS, noise=0.05, seed=2, pause_s=0.5)
    return biased, clean


def _heading_error_deg(res, ref) -> np.ndarray:
    d = res.steps["gyro_heading_rad"].to_numpy() - ref.steps["gyro_heading_rad"].to_numpy()
    return np.degrees(np.abs(np.angle(np.exp(1j * d))))


def test_still_recording_gives_the_bias():
    gb = gyro_bias_from_still(_still(30.0))
    assert gb.method == "still-recording"
    np.testing.assert_allclose(gb.bias_rads, BIAS, atol=5e-4)
    assert gb.still_s >= 25.0
    d = json.loads(json.dumps(gb.to_dict()))
    assert d["source"] == "still" and d["method"] == "still-recording"


@pytest.mark.parametrize("mode", ["still", "auto"])
def test_the_still_recording_removes_the_drift(walks, mode):
    """Held or tracked from there, the bias of the still recording leaves the heading of the unbiased phone;
    the walk's own estimate (the default) cannot see the bias about the vertical and drifts."""
    biased, clean = walks
    kw = {"modes": "forward", "heading": "gyro", "detector": "single-peak"}
    ref = run_pdr(clean, gyro_bias="off", **kw)
    got = run_pdr(biased, gyro_bias=mode, gyro_bias_start=gyro_bias_from_still(_still(30.0)), **kw)
    default = run_pdr(biased, **kw)
    assert len(got.steps) == len(ref.steps) == len(default.steps)
    assert _heading_error_deg(got, ref).max() < HEADING_TOL_DEG
    # the drift the still recording removes: 0.03 rad/s about the vertical over the walk's 90 s
    assert _heading_error_deg(default, ref).max() > 20 * HEADING_TOL_DEG
    rec = got.info["gyro_bias"]
    assert rec["method"] == ("still-recording" if mode == "still" else "still-recording+online")
    assert rec["source"] == "still"


def test_chunked_run_gives_the_same_trajectory(walks, tmp_path):
    biased, _ = walks
    p = tmp_path / "walk.csv"
    write_gaitml_csv(biased, p)
    start = gyro_bias_from_still(_still(30.0))
    for mode in ("still", "auto"):
        kw = {"modes": "forward", "detector": "single-peak", "gyro_bias": mode, "gyro_bias_start": start}
        whole = run_pdr(read_recording(p), **kw)
        chunked = long_pdr(p, **kw, chunk_s=20.0, margin_s=5.0, progress=False)
        np.testing.assert_array_equal(chunked.steps["peak"].to_numpy(), whole.steps["peak"].to_numpy())
        dxy = chunked.trajectory[["x_m", "y_m"]].to_numpy() - whole.trajectory[["x_m", "y_m"]].to_numpy()
        assert np.hypot(dxy[:, 0], dxy[:, 1]).max() < 1e-3
        a, b = whole.info["gyro_bias"], chunked.info["gyro_bias"]
        assert (a["method"], a.get("source")) == (b["method"], b.get("source"))
        np.testing.assert_allclose(b["bias_rads"], a["bias_rads"], atol=1e-6)


@pytest.mark.parametrize("chunked", [False, True])
def test_cli_takes_a_still_recording_and_its_json(walks, tmp_path, capsys, monkeypatch, chunked):
    biased, clean = walks
    walk, still = tmp_path / "walk.csv", tmp_path / "still.csv"
    write_gaitml_csv(biased, walk)
    write_gaitml_csv(_still(30.0), still)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1 if chunked else 10**12)
    capsys.readouterr()
    assert main(["pdr", str(walk), "--heading", "gyro", "--detector", "single-peak", "--gyro-bias-from", str(still), "--json"]) == 0
    out = capsys.readouterr()
    obj = json.loads(out.out)
    gb = obj["gyro_bias"]
    assert gb["method"].startswith("still-recording") and gb["source"] == str(still)
    np.testing.assert_allclose(gb["bias_rads"] if gb["method"] == "still-recording" else gb["start_bias_rads"], BIAS, atol=5e-4)
    assert f"gyroscope bias from {still}" in out.err
    # the run's JSON carries the bias to the next walk of the same phone
    saved = tmp_path / "bias.json"
    saved.write_text(out.out)
    assert read_gyro_bias_json(saved).method == "file"
    assert (
        main(
            [
                "pdr",
                str(walk),
                "--heading",
                "gyro",
                "--detector",
                "single-peak",
                "--gyro-bias-from",
                str(saved),
                "--gyro-bias",
                "still",
                "--json",
            ]
        )
        == 0
    )
    again = json.loads(capsys.readouterr().out)
    assert again["gyro_bias"]["method"] == "file" and again["gyro_bias"]["source"] == str(saved)
    ref = run_pdr(clean, modes="forward", heading="gyro", detector="single-peak", gyro_bias="off")
    end = np.asarray(again["end_xy_m"])
    assert np.hypot(*(end - ref.end_xy_m)) < 0.02 * ref.distance_m  # the unbiased phone's end point
    # the text summary says where the bias came from
    assert main(["pdr", str(walk), "--detector", "single-peak", "--gyro-bias-from", str(saved)]) == 0
    assert f"from {saved} (file), then tracked online" in capsys.readouterr().out


def _refused(capsys, argv) -> str:
    capsys.readouterr()
    assert main(argv) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_a_bad_still_recording_is_refused_with_one_line_and_no_output(walks, tmp_path, capsys):
    biased, _ = walks
    walk = tmp_path / "walk.csv"
    write_gaitml_csv(biased, walk)
    out = tmp_path / "traj.csv"
    cases = {
        "short": (_still(3.0), "still for"),
        "moving": (synth_walk([("walk", 40, 0.0)], gyro_bias_rads=BIAS), "record the phone lying untouched"),
        "deg-per-s": (_still(30.0, np.degrees(BIAS)), "--gyr-unit"),
    }
    for name, (rec, words) in cases.items():
        p = tmp_path / f"{name}.csv"
        write_gaitml_csv(rec, p)
        line = _refused(capsys, ["pdr", str(walk), "--gyro-bias-from", str(p), "--out", str(out)])
        assert words in line, line
        assert not out.exists()
    with pytest.raises(InputError, match="no gyroscope"):
        gyro_bias_from_still(_still(30.0, gyr=False))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"gyro_bias": {"method": "none", "bias_rads": [0, 0, 0]}}))
    assert "no measured gyroscope bias" in _refused(capsys, ["pdr", str(walk), "--gyro-bias-from", str(bad), "--out", str(out)])
    assert "nothing to do" in _refused(capsys, ["pdr", str(walk), "--gyro-bias-from", str(bad), "--gyro-bias", "off"])
    assert _refused(capsys, ["pdr", str(walk), "--gyro-bias-from", str(tmp_path / "missing.csv"), "--out", str(out)])
    assert not out.exists()


@pytest.mark.parametrize("chunked", [False, True])
def test_a_still_recording_at_another_rate_is_flagged_even_resampled(walks, tmp_path, capsys, monkeypatch, chunked):
    """A still recording made at another rate than the walk is said so in one stderr line and in the JSON's
    gyro_bias record, also when the input options resample both to one rate (--sampling-rate-hz): the warning
    compares the rates the two files were made at, not the rate they are read at."""
    biased, _ = walks
    walk, fast, same = tmp_path / "walk.csv", tmp_path / "still_fast.csv", tmp_path / "still_same.csv"
    write_gaitml_csv(biased, walk)
    write_gaitml_csv(_still(30.0, fs=2 * FS), fast)
    write_gaitml_csv(_still(30.0), same)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1 if chunked else 10**12)
    base = ["pdr", str(walk), "--detector", "single-peak", "--json"]
    for extra in ([], ["--sampling-rate-hz", f"{FS:g}"]):
        capsys.readouterr()
        assert main([*base, "--gyro-bias-from", str(fast), *extra]) == 0
        out = capsys.readouterr()
        warned = [ln for ln in out.err.splitlines() if "was made at" in ln]
        assert len(warned) == 1, (extra, out.err)
        assert f"{2 * FS:.1f} Hz" in warned[0] and f"the walk at {FS:.1f} Hz" in warned[0]
        gb = json.loads(out.out)["gyro_bias"]
        assert gb["still_rate_warning"] == warned[0].removeprefix("gaitml: warning: ")
        assert main([*base[:-1], "--gyro-bias-from", str(fast), *extra]) == 0  # the text summary says it too
        assert f"gyroscope bias: {gb['still_rate_warning']}" in capsys.readouterr().out
        # the same phone at the walk's rate: nothing said
        assert main([*base, "--gyro-bias-from", str(same), *extra]) == 0
        out = capsys.readouterr()
        assert "was made at" not in out.err
        assert "still_rate_warning" not in json.loads(out.out)["gyro_bias"]


@pytest.mark.parametrize(
    "field",
    [
        {"still_s": "x"},
        {"still_s": float("nan")},
        {"still_s": -1.0},
        {"n_still_windows": "many"},
        {"n_still_windows": [1]},
        {"method": ["still"]},
    ],
)
def test_a_malformed_bias_json_is_refused_with_one_line_and_no_output(walks, tmp_path, capsys, field):
    """A JSON whose gyro_bias record holds a malformed still time, window count or method is refused by
    read_gyro_bias_json in one line naming the field (before: an internal error, or a NaN still time that
    broke the JSON output after the trajectory had been written)."""
    biased, _ = walks
    walk, out, bad = tmp_path / "walk.csv", tmp_path / "traj.csv", tmp_path / "bias.json"
    write_gaitml_csv(biased, walk)
    bad.write_text(json.dumps({"gyro_bias": {"method": "still", "bias_rads": list(BIAS), "still_s": 30.0, **field}}))
    with pytest.raises(InputError, match=next(iter(field))):
        read_gyro_bias_json(bad)
    line = _refused(capsys, ["pdr", str(walk), "--gyro-bias-from", str(bad), "--json", "--out", str(out)])
    assert next(iter(field)) in line and "internal error" not in line, line
    assert not out.exists()
