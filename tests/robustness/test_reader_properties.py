"""Property-based tests: hostile files give a correct Recording or an InputError, never a crash."""

from __future__ import annotations

import numpy as np
import pandas as pd
from hypothesis import given
from hypothesis import strategies as st

from gaitml import InputError
from gaitml.consts import ACC_LIMIT_MS2, GYR_FULL_SCALE_MAX_RADS, GYR_LIMIT_RADS
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.recording import Recording, check_gyr_unit, max_bridge_s
from tests.robustness._hyp import count, hyp_settings

SETTINGS = hyp_settings(150)

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
anyfloat = st.one_of(finite, st.just(float("nan")), st.just(float("inf")), st.just(-float("inf")), st.just(1e300))
#: plausible sensor values: with the scale 0.01 below, |acc - g| stays under 30 m/s^2
plausible = st.floats(min_value=-3e3, max_value=3e3, allow_nan=False)


@st.composite
def tables(draw):
    n = draw(st.integers(min_value=0, max_value=40))
    t_mode = draw(st.sampled_from(["uniform", "uniform", "jitter", "jitter", "duplicate", "decreasing", "random"]))
    base = np.arange(n) * 0.02
    if t_mode == "jitter":
        base = base + np.array(draw(st.lists(st.floats(0, 0.009), min_size=n, max_size=n)))
    elif t_mode == "duplicate" and n > 2:
        base[n // 2] = base[n // 2 - 1]
    elif t_mode == "decreasing" and n > 2:
        base[[1, 2]] = base[[2, 1]]
    elif t_mode == "random":
        base = np.array(draw(st.lists(anyfloat, min_size=n, max_size=n)))
    acc_scale = draw(st.sampled_from([1.0, 1.0, 1 / 9.81, 1e3]))
    corrupt = draw(st.booleans())  # half of the files hold only plausible values, so some get through
    value = anyfloat if corrupt else plausible
    acc = np.array(draw(st.lists(st.tuples(value, value, value), min_size=n, max_size=n))).reshape(n, 3) * 0.01
    acc[:, 2] += 9.81
    acc *= acc_scale
    df = pd.DataFrame({"t": base, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2]})
    if draw(st.booleans()):
        df["label"] = draw(st.lists(st.sampled_from(["walk", "run", ""] if corrupt else ["walk", "run"]), min_size=n, max_size=n))
    drop = draw(st.sampled_from([None, None, None, "acc_y", "t"]))
    if drop:
        df = df.drop(columns=drop)
    return df


@SETTINGS
@given(df=tables(), truncate=st.integers(min_value=-1, max_value=400))
def test_gaitml_csv_reader_never_crashes(tmp_path_factory, df, truncate):
    p = tmp_path_factory.mktemp("h") / "x.csv"
    text = df.to_csv(index=False)
    if truncate >= 0:
        text = text[:truncate]
    p.write_text(text)
    try:
        rec = read_recording(p)
    except InputError as exc:
        assert "\n" not in str(exc)
        count("read_recording(gaitml-csv)", "refused")
        return
    count("read_recording(gaitml-csv)", "ran")
    assert isinstance(rec, Recording)
    assert np.isfinite(rec.acc).all() and rec.n_samples >= 1
    med = np.median(np.linalg.norm(rec.acc, axis=1))
    assert not (0.5 <= med <= 2.0) and med <= 50  # g- or mg-scaled data is never silently accepted


@SETTINGS
@given(
    n=st.integers(min_value=1, max_value=60),
    fs=st.floats(min_value=5.0, max_value=1000.0),
    seed=st.integers(min_value=0, max_value=10_000),
)
def test_round_trip_any_rate(tmp_path_factory, n, fs, seed):
    rng = np.random.default_rng(seed)
    # noise small enough that |acc| stays near gravity (a random draw near 1 m/s^2 would rightly read as g)
    rec = Recording(acc=rng.normal(0, 1, (n, 3)) + [0, 0, 9.81], gyr=rng.normal(0, 1, (n, 3)), sampling_rate_hz=fs)
    p = write_gaitml_csv(rec, tmp_path_factory.mktemp("r") / "r.csv")
    count("write_gaitml_csv + read_recording", "ran")
    if n == 1:
        try:
            read_recording(p)
        except InputError as exc:
            assert "at least 2" in str(exc)
        return
    back = read_recording(p)
    np.testing.assert_array_equal(back.acc, rec.acc)
    assert abs(back.sampling_rate_hz - fs) <= 1e-6 * max(1.0, fs)


# ------------------------------------------------------------------ issue 17: timestamps, gaps, ranges, units
@st.composite
def timestamps(draw):
    """Increasing (mostly) timestamps with any mix of jitter, small and huge gaps, ms/ns scales."""
    n = draw(st.integers(min_value=0, max_value=400))
    fs = draw(st.sampled_from([5.0, 50.0, 100.0, 204.8, 1000.0]))
    dt = np.full(max(n - 1, 0), 1 / fs)
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    if n > 1 and draw(st.booleans()):
        dt = dt * (1 + rng.uniform(-0.4, 0.4, n - 1))
    for _ in range(draw(st.integers(0, 3))):
        if n > 1:
            dt[rng.integers(0, n - 1)] = draw(st.sampled_from([0.3, 0.99, 1.01, 5.0, 3600.0, 1e7, 1e12, 0.0, -0.01]))
    scale = draw(st.sampled_from([1.0, 1.0, 1.0, 1e3, 1e9, 1e-3]))
    t = (draw(st.sampled_from([0.0, 1.7e9])) + np.concatenate([[0.0], np.cumsum(dt)])[:n]) * scale
    return t


@SETTINGS
@given(t=timestamps(), rate=st.sampled_from([None, None, 50.0, 1000.0]))
def test_from_timestamps_never_invents_long_stretches(t, rate):
    n = len(t)
    acc = np.tile([0.1, 0.2, 9.8], (n, 1))
    try:
        rec = Recording.from_timestamps(t, acc, sampling_rate_hz=rate)
    except InputError as exc:
        assert "\n" not in str(exc)
        count("Recording.from_timestamps", "refused")
        return
    count("Recording.from_timestamps", "ran")
    dt = np.diff(t)
    assert (dt > 0).all()
    assert dt.max() <= max_bridge_s(float(np.median(dt)))  # no gap beyond the limit was bridged
    assert rec.n_samples <= 100 * n + 1000  # memory bounded by the input
    assert abs(rec.duration_s - (t[-1] - t[0])) <= 2 / rec.sampling_rate_hz + 1e-6


@SETTINGS
@given(t=timestamps())
def test_segments_partition_the_samples(t):
    n = len(t)
    acc = np.tile([0.1, 0.2, 9.8], (n, 1))
    try:
        segs = Recording.segments_from_timestamps(t, acc)
    except InputError as exc:
        assert "\n" not in str(exc)
        count("Recording.segments_from_timestamps", "refused")
        return
    count("Recording.segments_from_timestamps", "ran")
    firsts = [s.meta["segment"]["first_sample"] for s in segs]
    lasts = [s.meta["segment"]["last_sample"] for s in segs]
    assert firsts == sorted(firsts) and all(a < b for a, b in zip(lasts, firsts[1:], strict=False))
    assert sum(s.meta["n_original_samples"] for s in segs) == sum(b - a + 1 for a, b in zip(firsts, lasts, strict=True))
    limit = max_bridge_s(float(np.median(np.diff(t))))
    for s, a, b in zip(segs, firsts, lasts, strict=True):
        assert s.meta["segment"]["of"] == len(segs)
        assert np.diff(t[a : b + 1]).max() <= limit
        if b + 1 < n:
            assert t[b + 1] - t[b] > limit  # each cut is at a long gap


@SETTINGS
@given(
    n=st.integers(min_value=20, max_value=300),  # one value cannot move the median (unit checks) then
    where=st.sampled_from(["acc", "gyr", "none"]),
    value=st.sampled_from([1e308, -1e308, 1e30, 4e3, 5e3, 400.0, 300.0, -1e4, 5e-324]),
    seed=st.integers(0, 1000),
)
def test_values_beyond_any_sensor_are_refused_and_nothing_else(n, where, value, seed):
    rng = np.random.default_rng(seed)
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, 9.81]
    gyr = rng.normal(0, 0.5, (n, 3))
    i = int(rng.integers(0, n))
    if where != "none":
        (acc if where == "acc" else gyr)[i, int(rng.integers(0, 3))] = value
    beyond = (np.abs(acc) > ACC_LIMIT_MS2).any() or (np.abs(gyr) > GYR_LIMIT_RADS).any()
    try:
        rec = Recording(acc=acc, gyr=gyr, sampling_rate_hz=50.0)
    except InputError as exc:
        count("Recording (sensor ranges)", "refused")
        # a value beyond the range is named; one beyond any phone gyro's full scale (4000 deg/s) may move
        # the 99th percentile of a short recording into the deg/s refusal, which is a right reading too
        beyond_full_scale = (np.abs(gyr) > GYR_FULL_SCALE_MAX_RADS).any()
        assert beyond or beyond_full_scale, str(exc)
        assert "beyond any sensor's range" in str(exc) or (beyond_full_scale and "deg/s" in str(exc)), str(exc)
        return
    count("Recording (sensor ranges)", "ran")
    assert not beyond
    assert np.isfinite(np.linalg.norm(rec.acc, axis=1)).all()


@SETTINGS
@given(
    amp=st.floats(0.05, 14.0),
    sharp=st.floats(0.0, 12.0),
    freq=st.floats(0.3, 3.5),
    noise=st.floats(0.0, 0.5),
    rest=st.floats(0.0, 0.8),
    seed=st.integers(0, 1000),
)
def test_human_motion_in_rad_s_is_never_refused_and_in_deg_s_is_caught(amp, sharp, freq, noise, rest, seed):
    """Gait-like rad/s gyro (peaks up to ~26 rad/s, like a thigh while sprinting) is accepted; 57.3x it is refused."""
    rng = np.random.default_rng(seed)
    n = 1500
    ph = 2 * np.pi * freq * np.arange(n) / 50.0
    g = np.column_stack([amp * np.sin(ph) + sharp * np.sin(ph) ** 9, 0.4 * amp * np.sin(2 * ph), 0.3 * amp * np.cos(ph)])
    g += rng.normal(0, noise, (n, 3))
    g[: int(rest * n)] = rng.normal(0, 0.003, (int(rest * n), 3))  # the phone lying still first
    warning = check_gyr_unit(g)  # never raises
    count("check_gyr_unit (rad/s motion)", "warned" if warning else "ran")
    med = float(np.median(np.linalg.norm(g, axis=1)))
    if med * np.degrees(1.0) > 15.0:  # as deg/s its median is beyond any human motion in rad/s
        try:
            check_gyr_unit(np.degrees(g))
        except InputError as exc:
            assert "deg/s" in str(exc)
            count("check_gyr_unit (deg/s motion)", "refused")
        else:
            raise AssertionError(f"deg/s gyro with median {med * 57.3:.1f} accepted as rad/s")
