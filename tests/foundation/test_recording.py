"""Recording: validation at construction and the resampling constructor."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml import InputError
from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording


def _acc(n, rng=None):
    rng = rng or np.random.default_rng(0)
    a = rng.normal(0, 0.5, (n, 3))
    a[:, 2] += GRAVITY_MS2
    return a


def test_valid_recording_properties():
    rec = Recording(acc=_acc(100), sampling_rate_hz=50.0, labels=["walk"] * 100)
    assert rec.n_samples == 100
    assert rec.duration_s == pytest.approx(2.0)
    assert rec.t_s[1] == pytest.approx(0.02)
    assert not rec.has_gyr
    with pytest.raises(ValueError):
        rec.acc[0, 0] = 1.0  # read-only


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"acc": np.zeros((10, 2))}, r"shape \(n, 3\)"),
        ({"acc": np.zeros((0, 3))}, "no samples"),
        ({"sampling_rate_hz": 0}, "positive"),
        ({"sampling_rate_hz": float("nan")}, "positive"),
        ({"gyr": np.zeros((9, 3))}, "gyr` has 9 samples"),
        ({"labels": ["a"] * 3}, "labels` must have shape"),
    ],
)
def test_invalid_construction(kwargs, match):
    base = {"acc": _acc(10), "sampling_rate_hz": 50.0}
    base.update(kwargs)
    with pytest.raises(InputError, match=match):
        Recording(**base)


def test_nan_and_inf_are_refused_with_position():
    a = _acc(20)
    a[7, 1] = np.nan
    with pytest.raises(InputError, match="NaN/inf.*sample 7"):
        Recording(acc=a, sampling_rate_hz=50)
    a[7, 1] = np.inf
    with pytest.raises(InputError, match="NaN/inf"):
        Recording(acc=a, sampling_rate_hz=50)


def test_acc_in_g_is_refused_with_hint_and_converted_on_request():
    a = _acc(200) / GRAVITY_MS2
    with pytest.raises(InputError, match="acc_unit='g'"):
        Recording(acc=a, sampling_rate_hz=50)
    rec = Recording.from_arrays(a, 50, acc_unit="g")
    assert np.median(np.linalg.norm(rec.acc, axis=1)) == pytest.approx(GRAVITY_MS2, rel=0.05)
    assert rec.meta["converted"] == ["acc from g"]


def test_acc_in_milli_g_is_refused():
    with pytest.raises(InputError, match="implausibly large"):
        Recording(acc=_acc(50) * 1000 / GRAVITY_MS2, sampling_rate_hz=50)


def test_gyro_in_deg_s_is_refused_and_converted_on_request():
    g = np.random.default_rng(1).normal(0, 200, (200, 3))
    with pytest.raises(InputError, match="deg/s"):
        Recording(acc=_acc(200), gyr=g, sampling_rate_hz=50)
    rec = Recording.from_arrays(_acc(200), 50, gyr=g, gyr_unit="deg/s")
    np.testing.assert_allclose(rec.gyr, np.deg2rad(g))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_resampling_jittered_sine_is_accurate(seed):
    # An Oxford-like log: ~200 Hz with 30 % timing jitter, a 2 Hz gait fundamental.
    rng = np.random.default_rng(seed)
    fs = 200.0
    n = 6000
    t = np.sort(np.arange(n) / fs + rng.uniform(-0.3, 0.3, n) / fs) + 12.345
    amp, f = 2.0, 2.0
    acc = np.column_stack([amp * np.sin(2 * np.pi * f * t), np.zeros(n), np.full(n, GRAVITY_MS2)])
    rec = Recording.from_timestamps(t, acc, sampling_rate_hz=100.0)
    grid = t[0] + rec.t_s
    err = np.abs(rec.acc[:, 0] - amp * np.sin(2 * np.pi * f * grid))
    assert err.max() < 1e-3 * amp
    assert rec.meta["resampled"] is True
    assert rec.meta["original_rate_hz"] == pytest.approx(fs, rel=0.05)
    assert rec.meta["jitter_s"] > 0
    assert rec.meta["gaps"] == []


def test_resampling_error_within_linear_interpolation_bound():
    # Coarser sampling: the error obeys the documented bound max_dt^2 max|f''| / 8.
    rng = np.random.default_rng(42)
    t = np.sort(np.arange(3000) / 100.0 + rng.uniform(-0.3, 0.3, 3000) / 100.0)
    amp, f = 2.0, 1.3
    acc = np.column_stack([amp * np.sin(2 * np.pi * f * t), np.zeros(3000), np.full(3000, GRAVITY_MS2)])
    rec = Recording.from_timestamps(t, acc, sampling_rate_hz=100.0)
    err = np.abs(rec.acc[:, 0] - amp * np.sin(2 * np.pi * f * (t[0] + rec.t_s)))
    bound = np.diff(t).max() ** 2 * amp * (2 * np.pi * f) ** 2 / 8
    assert err.max() <= bound


def test_resampling_reports_gaps_and_shifts_reference():
    t = np.concatenate([np.arange(0, 1, 0.01), np.arange(1.5, 2.5, 0.01)]) + 100.0
    acc = _acc(len(t))
    rec = Recording.from_timestamps(t, acc, sampling_rate_hz=100.0, reference={"steps_t_s": [100.5, 101.7]})
    assert len(rec.meta["gaps"]) == 1
    assert rec.meta["gaps"][0][1] == pytest.approx(0.51, abs=1e-6)
    np.testing.assert_allclose(rec.reference["steps_t_s"], [0.5, 1.7])
    assert rec.meta["t0_original_s"] == pytest.approx(100.0)


def test_uniform_timestamps_are_kept_without_interpolation():
    t = np.arange(500) / 204.8
    acc = _acc(500)
    rec = Recording.from_timestamps(t, acc)
    assert rec.sampling_rate_hz == pytest.approx(204.8)
    assert rec.meta["resampled"] is False
    np.testing.assert_array_equal(rec.acc, acc)


def test_labels_are_sample_and_hold():
    t = np.array([0.0, 0.013, 0.021, 0.034, 0.04])
    labels = ["a", "a", "b", "b", "c"]
    rec = Recording.from_timestamps(t, _acc(5), labels=labels, sampling_rate_hz=100.0)
    assert rec.labels.tolist() == ["a", "a", "a", "b", "c"]


@pytest.mark.parametrize(
    "t, match",
    [
        ([0.0, 0.01, 0.01, 0.03], "duplicate timestamp"),
        ([0.0, 0.02, 0.01, 0.03], "timestamps decrease at sample 2"),
        ([0.0], "at least 2"),
        ([0.0, np.nan, 0.2, 0.3], "NaN/inf"),
    ],
)
def test_bad_timestamps(t, match):
    with pytest.raises(InputError, match=match):
        Recording.from_timestamps(np.asarray(t), _acc(len(t)))


def test_slice_shifts_reference_times():
    rec = Recording(acc=_acc(100), sampling_rate_hz=10.0, reference={"steps_t_s": np.array([1.0, 5.0, 9.0])})
    part = rec.slice(40, 80)
    assert part.n_samples == 40
    np.testing.assert_allclose(part.reference["steps_t_s"], [1.0])


def test_require_helpers():
    rec = Recording(acc=_acc(10), sampling_rate_hz=10.0)
    with pytest.raises(InputError, match="needs a gyroscope"):
        rec.require_gyr("pseudo-std")
    with pytest.raises(InputError, match="too short for one window"):
        rec.require_samples(50, "one window")


@pytest.mark.parametrize(
    "fs, match",
    [(0.05, "too low for gait.*ms or ns"), (2e6, "above 10000 Hz"), (float("inf"), "positive number")],
)
def test_implausible_rates(fs, match):
    with pytest.raises(InputError, match=match):
        Recording(acc=_acc(20), sampling_rate_hz=fs)


def test_timestamps_in_ms_are_refused():
    t_ms = np.arange(100) * 20.0  # 50 Hz written in ms
    with pytest.raises(InputError, match="ms or ns"):
        Recording.from_timestamps(t_ms, _acc(100))
    with pytest.raises(InputError, match="above 10000"):
        Recording.from_timestamps(np.arange(100) / 50.0, _acc(100), sampling_rate_hz=1e9)


def test_acceleration_without_gravity_is_refused():
    with pytest.raises(InputError, match="no gravity"):
        Recording(acc=np.zeros((50, 3)), sampling_rate_hz=50)
    with pytest.raises(InputError, match="no gravity"):
        Recording(acc=np.random.default_rng(0).normal(0, 0.1, (50, 3)), sampling_rate_hz=50)


def test_gyro_deg_s_on_an_ordinary_walk_is_refused():
    t = np.arange(500) / 50
    gyr_degs = np.column_stack([25 * np.sin(2 * np.pi * t), 30 * np.cos(2 * np.pi * t), np.full(500, 20.0)])
    with pytest.raises(InputError, match="deg/s"):
        Recording(acc=_acc(500), gyr=gyr_degs, sampling_rate_hz=50)
