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


def test_running_foot_is_told_from_unit_mistakes_by_its_rest_level():
    """A foot-mounted sensor of a runner has a median |acc| of 4-5 g (up to and above 50 m/s^2) and its 5th
    percentile near 1 g: accepted in m/s^2, also at 50 Hz (resampled as predict does, which smooths its foot
    flats away); the same signal in g or in milli-g is refused with the one-line hint, and accepted in g when asked."""
    from gaitml.models import resample_recording
    from gaitml.simulate.foot import simulate_foot

    medians = []
    for seed in (8, 10, 111):
        rec = simulate_foot(modes=("run",), duration_s=30.0, sampling_rate_hz=100.0, seed=seed)
        for r in (rec, resample_recording(rec, 50.0)):  # the unit check passes in m/s^2, at both rates
            medians.append(float(np.median(np.linalg.norm(r.acc, axis=1))))
            fs = r.sampling_rate_hz
            Recording(acc=r.acc, gyr=r.gyr, sampling_rate_hz=fs)
            in_g = r.acc / GRAVITY_MS2
            with pytest.raises(InputError, match=r"in g, not m/s\^2.*acc_unit='g'") as err:
                Recording(acc=in_g, gyr=r.gyr, sampling_rate_hz=fs)
            assert "\n" not in str(err.value)
            assert Recording.from_arrays(in_g, fs, gyr=r.gyr, acc_unit="g").meta["converted"] == ["acc from g"]
            with pytest.raises(InputError, match="implausibly large"):
                Recording(acc=in_g * 1000.0, gyr=r.gyr, sampling_rate_hz=fs)
    assert max(medians) > 50.0  # the median alone would call it milli-g


def test_milli_g_with_zero_rows_is_still_refused():
    """A logger's zero rows (sensor warm-up, dropped rows filled with 0) must not pass a milli-g file as m/s^2:
    the low percentile that tells a runner's foot from milli-g is taken over the samples that are not zero."""
    a = _acc(2000) * 1000 / GRAVITY_MS2
    for rows in (slice(0, 140), slice(None, None, 15)):  # 7 % at the start, or scattered
        z = a.copy()
        z[rows] = 0.0
        with pytest.raises(InputError, match="implausibly large"):
            Recording(acc=z, sampling_rate_hz=50)


def test_linear_acceleration_is_refused_as_no_gravity_not_as_g():
    """Gravity removed (a phone's linear-acceleration export) has a median of a few m/s^2 and a low tail under 2
    like a runner's foot in g; its mean vector is near zero, so it is refused as having no gravity (the "in g"
    hint would make it look right once multiplied by 9.81); a runner's foot in g still gets the g hint."""
    from scipy.ndimage import uniform_filter1d

    from gaitml.simulate.foot import simulate_foot

    rng = np.random.default_rng(3)
    # body accelerations without gravity: band-limited noise of a few m/s^2 on every axis (its magnitude passes
    # through zero, its mean vector cancels)
    lin = uniform_filter1d(rng.normal(0, 12.0, (3000, 3)), 10, axis=0)
    lin -= uniform_filter1d(lin, 100, axis=0)
    with pytest.raises(InputError, match="no gravity") as err:
        Recording(acc=lin, sampling_rate_hz=50)
    assert "acc_unit='g'" not in str(err.value)
    small = lin / 5.0  # a calm hand-held walk: a median under 2, where the "in g" hint used to come first
    assert np.median(np.linalg.norm(small, axis=1)) < 2.0
    for a, unit in ((small, "m/s^2"), (small, "g"), (lin, "g")):  # never accepted once multiplied by 9.81
        with pytest.raises(InputError, match="no gravity"):
            Recording.from_arrays(a, 50, acc_unit=unit)
    # a phone turned through six attitudes at rest (a calibration) has a mean vector near zero too, and is accepted
    calib = np.repeat(np.vstack([np.eye(3), -np.eye(3)]) * GRAVITY_MS2, 500, axis=0) + rng.normal(0, 0.05, (3000, 3))
    Recording(acc=calib, sampling_rate_hz=50)
    foot = simulate_foot(modes=("run",), duration_s=30.0, sampling_rate_hz=100.0, seed=8)
    with pytest.raises(InputError, match=r"in g, not m/s\^2"):
        Recording(acc=foot.acc / GRAVITY_MS2, gyr=foot.gyr, sampling_rate_hz=100.0)


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


# ---------------------------------------------------------------- issue 17: gaps, ranges, gyro unit
def test_gap_too_long_to_bridge_is_refused_with_position_and_length():
    t = np.arange(1000) / 100.0
    t[600:] += 1e7  # would be 10^9 samples at 100 Hz
    with pytest.raises(InputError, match=r"1e\+07 s gap in the timestamps after sample 599 \(t = 5.99 s .*gaitml split FILE --out DIR"):
        Recording.from_timestamps(t, _acc(1000))
    # the limit: the longer of MAX_BRIDGE_S and ten sampling intervals
    from gaitml.recording import MAX_BRIDGE_S, max_bridge_s

    assert max_bridge_s(0.01) == MAX_BRIDGE_S == 1.0
    assert max_bridge_s(0.2) == pytest.approx(2.0)
    t2 = np.arange(1000) / 100.0
    t2[600:] += 0.95  # a 0.96 s gap is bridged and reported
    rec = Recording.from_timestamps(t2, _acc(1000))
    assert rec.meta["gaps"] == [[5.99, 0.96]]
    t2[600:] += 0.1  # 1.06 s is not
    with pytest.raises(InputError, match="1.06 s gap"):
        Recording.from_timestamps(t2, _acc(1000))
    # a caller may allow a longer bridge explicitly
    assert Recording.from_timestamps(t2, _acc(1000), max_gap_s=2.0).n_samples == 1105


def test_segments_from_timestamps_cut_at_long_gaps():
    t = np.concatenate([np.arange(300) / 100, 50 + np.arange(200) / 100, [500.0], 900 + np.arange(100) / 100])
    labels = np.array(["a"] * 300 + ["b"] * 200 + ["c"] + ["d"] * 100)
    segs = Recording.segments_from_timestamps(
        t, _acc(len(t)), labels=labels, meta={"id": "rec"}, reference={"steps_t_s": [1.0, 2.0, 51.0, 900.5, 700.0]}
    )
    assert [s.n_samples for s in segs] == [300, 200, 100]
    assert [s.name for s in segs] == ["rec#0", "rec#1", "rec#2"]
    assert segs[1].meta["segment"] == {"index": 1, "of": 3, "first_sample": 300, "last_sample": 499, "t_start_s": 50.0, "t_end_s": 51.99}
    assert segs[0].meta["segments_dropped"] == 1  # the lone sample at 500 s
    assert set(segs[2].labels) == {"d"}
    np.testing.assert_allclose(segs[0].reference["steps_t_s"], [1.0, 2.0])
    np.testing.assert_allclose(segs[1].reference["steps_t_s"], [1.0])
    np.testing.assert_allclose(segs[2].reference["steps_t_s"], [0.5])
    assert segs[2].reference["n_steps_true"] == 1
    one = Recording.segments_from_timestamps(np.arange(100) / 50, _acc(100))
    assert len(one) == 1 and one[0].n_samples == 100


@pytest.mark.parametrize(
    ("col", "value", "match"),
    [
        ("gyr", 1e308, r"gyr_y = 1e\+308 at sample 7 .*\|gyr\| <= 349.1 rad/s"),
        ("gyr", 400.0, r"gyr_y = 400 at sample 7 .*pass --gyr-unit deg/s"),  # plausible in deg/s: says so
        ("acc", -1e308, r"acc_y = -1e\+308 at sample 7 .*\|acc\| <= 4903 m/s\^2"),
        ("acc", 6000.0, r"acc_y = 6000 at sample 7 .*milli-g"),
    ],
)
def test_values_beyond_any_sensor_range_are_refused(col, value, match):
    acc, gyr = _acc(500), np.random.default_rng(3).normal(0, 0.5, (500, 3))
    (acc if col == "acc" else gyr)[7, 1] = value
    with pytest.raises(InputError, match=match):
        Recording(acc=acc, gyr=gyr, sampling_rate_hz=50)
    with pytest.raises(InputError, match=match):  # before resampling: interpolating 1e308 would overflow
        Recording.from_timestamps(np.arange(500) / 50 + np.r_[0, np.full(499, 1e-4)], acc, gyr=gyr)


def _jog_pocket_gyr(n=3000, fs=50.0, rest_s=0.0):
    t = np.arange(n) / fs
    ph = 2 * np.pi * 1.4 * t
    g = np.column_stack([9 * np.sin(ph) + 13 * np.sin(ph) ** 9, 3 * np.sin(2 * ph + 0.5), 2 * np.cos(ph)])
    g += np.random.default_rng(0).normal(0, 0.3, (n, 3))
    if rest_s:
        g[: int(rest_s * fs)] = np.random.default_rng(1).normal(0, 0.003, (int(rest_s * fs), 3))
    return g


def test_gyro_unit_judged_on_the_whole_distribution():
    from gaitml.recording import check_gyr_unit

    jog = _jog_pocket_gyr()
    mag = np.linalg.norm(jog, axis=1)
    assert np.percentile(mag, 99) > 21.5  # as fast as the WISDM jog of the issue, which was refused before
    # fast real motion in rad/s is accepted, with a warning since no rest level tells the units apart
    rec = Recording(acc=_acc(3000), gyr=jog, sampling_rate_hz=50)
    assert len(rec.meta["warnings"]) == 1 and "may be in deg/s" in rec.meta["warnings"][0]
    # ... and without one when the recording has a rad/s rest level (a still phone reads < 0.03 rad/s)
    assert check_gyr_unit(_jog_pocket_gyr(rest_s=4.0)) is None
    # the same motion in deg/s is refused: its median is 57x larger
    with pytest.raises(InputError, match=r"deg/s, not rad/s \(median \|gyr\| = \d{3}"):
        check_gyr_unit(np.degrees(jog))
    # a mostly still deg/s recording whose peaks no gyro could give in rad/s (p99 > 4000 deg/s = 69.8 rad/s)
    still = np.random.default_rng(2).normal(0, 0.5, (1000, 3))
    still[::20] = 150.0
    with pytest.raises(InputError, match="deg/s"):
        check_gyr_unit(still)
    assert check_gyr_unit(np.zeros((10, 3))) is None


def test_fast_timestamps_accepted_with_a_target_rate_and_upsampling_bounded():
    t = np.arange(2000) / 20000.0
    with pytest.raises(InputError, match="above 10000 Hz.*lower --sampling-rate-hz"):
        Recording.from_timestamps(t, _acc(2000))
    rec = Recording.from_timestamps(t, _acc(2000), sampling_rate_hz=1000.0)
    assert rec.n_samples == 100 and "anti-alias FIR low-pass" in rec.meta["resample_method"]  # issue 28: filtered before decimation
    with pytest.raises(InputError, match="more than 100x the original"):
        Recording.from_timestamps(np.arange(50) / 5.0, _acc(50), sampling_rate_hz=10_000.0)
