"""adaptive's periodicity-floor relief from the gyroscope's stride rhythm (``rhythm_min_periodicity``, stage 4, opt-in;
experiments/reports/tyrex-steps.md, perio section)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import bandpass
from gaitml.steps import get_detector
from gaitml.steps.adaptive import (
    MIN_PERIODICITY,
    RHYTHM_MIN_PERIODICITY,
    RHYTHM_STEP_TOLERANCE,
    adaptive_steps,
    rhythm_windows,
    swing_projection,
    swing_rhythm,
)

FS = 50.0


def _walk(seed: int, swing_stride_hz: float | None = 0.5, seconds: float = 60.0):
    """A walk at 1 step/s whose |acc| repeats weakly (bumps of 0.4-1.2 m/s^2 in band-limited noise of 1.6 m/s^2 std),
    and a gyroscope that turns with a stride rhythm (a 0.5 rad/s sine at ``swing_stride_hz``; None: sensor noise only)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, seconds, 1 / FS)
    steps = np.arange(3.0, seconds - 3.0, 1.0)
    mag = 9.81 + rng.normal(0, 0.01, len(t))
    for s in steps:
        mag += 0.8 * rng.uniform(0.5, 1.5) * np.exp(-0.5 * ((t - s) / 0.12) ** 2)
    mag += 1.6 * bandpass(rng.normal(0, 1, len(t)), 0.5, 4.0, FS, order=2)
    gyr = rng.normal(0, 0.005, (len(t), 3))
    if swing_stride_hz is not None:
        gyr[:, 2] += 0.5 * np.sin(2 * np.pi * swing_stride_hz * (t - 3.0)) * ((t > 3.0) & (t < seconds - 3.0))
    return mag, gyr, len(steps)


def _projection(g: np.ndarray, fs: float, seconds: float = 5.0):
    n = int(seconds * fs)
    return swing_projection(g, n, n, 1)


def test_swing_rhythm_reads_a_stride_and_not_noise_or_a_weak_turn():
    fs = 25.0
    t = np.arange(0, 5.0, 1 / fs)
    rng = np.random.default_rng(0)
    stride = np.c_[np.zeros_like(t), np.zeros_like(t), 0.5 * np.sin(2 * np.pi * 0.5 * t)] + rng.normal(0, 0.005, (len(t), 3))
    ok, P = swing_rhythm(*_projection(stride, fs), fs)
    assert ok[0] and P[0] == pytest.approx(2.0 * fs, abs=1.0)  # a 2 s stride, 1 s steps
    noise = rng.normal(0, 0.3, (len(t), 3))
    assert not swing_rhythm(*_projection(noise, fs), fs)[0][0]
    weak = stride * 0.2  # the same rhythm, turning at 0.07 rad/s RMS: below GYRO_MIN_RMS_RADS
    assert not swing_rhythm(*_projection(weak, fs), fs)[0][0]


def test_rhythm_windows_need_a_weak_window_and_a_matching_step():
    fs = 25.0
    t = np.arange(0, 5.0, 1 / fs)
    g = np.c_[np.zeros_like(t), np.zeros_like(t), 0.5 * np.sin(2 * np.pi * 0.5 * t)]  # 1 s steps
    proj = _projection(g, fs)
    proj = (np.repeat(proj[0], 4, axis=0), np.repeat(proj[1], 4))
    cad = {"period_s": np.array([1.0, 1.2, 0.5, 1.0]), "periodicity": np.array([0.2, 0.2, 0.2, 0.6])}
    # matching step (1.0; 1.2 is within 25 %), a half-step window (0.5 s) finds no relief, a periodic window needs none
    assert rhythm_windows(cad, proj, fs).tolist() == [True, True, False, False]
    assert rhythm_windows(cad, proj, fs, step_tolerance=0.1).tolist() == [True, False, False, False]


def test_off_by_default():
    # not adopted (round 3 of the perio section fails at admissibility): 0 is off, and so is any value at the floor
    assert RHYTHM_MIN_PERIODICITY == 0.0
    assert RHYTHM_STEP_TOLERANCE == 0.25
    mag, gyr, _ = _walk(0)
    a = adaptive_steps(mag, FS, gyr_rads=gyr)
    b = adaptive_steps(mag, FS, gyr_rads=gyr, rhythm_min_periodicity=MIN_PERIODICITY)
    assert np.array_equal(a["peak"], b["peak"]) and a["rhythm_peaks"] == b["rhythm_peaks"] == 0


def test_a_higher_periodicity_floor_does_not_turn_the_relief_on():
    # min_periodicity 0.4 (the evaluation's param_grid) with the relief at its default: no relief, no warning
    mag, gyr, _ = _walk(0)
    assert adaptive_steps(mag, FS, gyr_rads=gyr, min_periodicity=0.4)["rhythm_peaks"] == 0
    rec = Recording(acc=np.c_[np.zeros_like(mag), np.zeros_like(mag), mag], sampling_rate_hz=FS)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        get_detector("adaptive", min_periodicity=0.4).detect(rec)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_weakly_periodic_walk_with_a_stride_rhythm_is_counted_closer_to_the_truth(seed):
    mag, gyr, n_true = _walk(seed)
    plain = adaptive_steps(mag, FS, gyr_rads=gyr)
    relief = adaptive_steps(mag, FS, gyr_rads=gyr, rhythm_min_periodicity=0.15)
    assert len(plain["peak"]) < n_true - 8  # the periodicity floor drops many of these steps
    assert relief["rhythm_peaks"] > 0
    assert abs(len(relief["peak"]) - n_true) < abs(len(plain["peak"]) - n_true)
    assert len(relief["peak"]) <= n_true + 2


def test_no_relief_without_a_rhythm_or_without_a_gyroscope():
    mag, gyr, _ = _walk(1, swing_stride_hz=None)  # the phone does not turn
    assert np.array_equal(
        adaptive_steps(mag, FS, gyr_rads=gyr)["peak"], adaptive_steps(mag, FS, gyr_rads=gyr, rhythm_min_periodicity=0.15)["peak"]
    )
    assert np.array_equal(adaptive_steps(mag, FS)["peak"], adaptive_steps(mag, FS, rhythm_min_periodicity=0.15)["peak"])


def test_the_detector_warns_once_without_a_gyroscope_and_keeps_the_default_steps():
    mag, _, _ = _walk(2)
    rec = Recording(acc=np.c_[np.zeros_like(mag), np.zeros_like(mag), mag], sampling_rate_hz=FS)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        d = get_detector("adaptive", rhythm_min_periodicity=0.15).detect(rec)
    relief_warnings = [w for w in caught if "rhythm_min_periodicity" in str(w.message)]
    assert len(relief_warnings) == 1 and "no gyroscope" in str(relief_warnings[0].message)
    assert d.steps_.attrs["rhythm"] == {"ran": False, "candidates": 0, "peaks": 0}
    assert np.array_equal(d.steps_["peak"].to_numpy(), get_detector("adaptive").detect(rec).steps_["peak"].to_numpy())


def test_the_detector_reports_the_relief_and_checks_the_keywords():
    mag, gyr, _ = _walk(0)
    rec = Recording(acc=np.c_[np.zeros_like(mag), np.zeros_like(mag), mag], gyr=gyr, sampling_rate_hz=FS)
    a = get_detector("adaptive", rhythm_min_periodicity=0.15).detect(rec).steps_.attrs["rhythm"]
    assert a["ran"] and a["candidates"] >= a["peaks"] > 0
    with pytest.raises(InputError, match="rhythm_min_periodicity"):
        get_detector("adaptive", rhythm_min_periodicity=-0.1).detect(rec)
    with pytest.raises(InputError, match="rhythm_step_tolerance"):
        get_detector("adaptive", rhythm_step_tolerance=-0.1).detect(rec)


def test_a_chunked_run_counts_the_relief_over_the_whole_file(tmp_path):
    """``long_steps`` keeps the same steps as a whole-file run; ``attrs['rhythm']`` must count the relief's peaks of
    the whole file (each chunk's core once), not those of the last chunk read."""
    from gaitml.chunked_run import long_steps
    from gaitml.io import write_gaitml_csv

    mag, gyr, _ = _walk(0, seconds=240.0)
    rec = Recording(acc=np.c_[np.zeros_like(mag), np.zeros_like(mag), mag], gyr=gyr, sampling_rate_hz=FS)
    p = tmp_path / "walk.csv"
    write_gaitml_csv(rec, p)
    prm = {"rhythm_min_periodicity": 0.15}
    whole = get_detector("adaptive", **prm).detect(rec).steps_
    chunked = long_steps(p, detector="adaptive", detector_params=prm, chunk_s=60.0, margin_s=30.0, progress=False)
    assert np.array_equal(chunked["peak"].to_numpy(), whole["peak"].to_numpy())
    w, c = whole.attrs["rhythm"], chunked.attrs["rhythm"]
    assert w["ran"] and c["ran"] and w["peaks"] > 10
    # a peak near a chunk edge may be judged on a little less context than on the whole file: one per edge at most
    n_edges = 3
    assert abs(c["candidates"] - w["candidates"]) <= n_edges and abs(c["peaks"] - w["peaks"]) <= n_edges
