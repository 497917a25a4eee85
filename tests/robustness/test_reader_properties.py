"""Property-based tests: hostile files give a correct Recording or an InputError, never a crash."""

from __future__ import annotations

import numpy as np
import pandas as pd
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gaitml import InputError
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.recording import Recording

SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
anyfloat = st.one_of(finite, st.just(float("nan")), st.just(float("inf")), st.just(-float("inf")), st.just(1e300))


@st.composite
def tables(draw):
    n = draw(st.integers(min_value=0, max_value=40))
    t_mode = draw(st.sampled_from(["uniform", "jitter", "duplicate", "decreasing", "random"]))
    base = np.arange(n) * 0.02
    if t_mode == "jitter":
        base = base + np.array(draw(st.lists(st.floats(0, 0.009), min_size=n, max_size=n)))
    elif t_mode == "duplicate" and n > 2:
        base[n // 2] = base[n // 2 - 1]
    elif t_mode == "decreasing" and n > 2:
        base[[1, 2]] = base[[2, 1]]
    elif t_mode == "random":
        base = np.array(draw(st.lists(anyfloat, min_size=n, max_size=n)))
    acc_scale = draw(st.sampled_from([1.0, 1 / 9.81, 1e3]))
    acc = np.array(draw(st.lists(st.tuples(anyfloat, anyfloat, anyfloat), min_size=n, max_size=n))).reshape(n, 3) * 0.01
    acc[:, 2] += 9.81
    acc *= acc_scale
    df = pd.DataFrame({"t": base, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2]})
    if draw(st.booleans()):
        df["label"] = draw(st.lists(st.sampled_from(["walk", "run", ""]), min_size=n, max_size=n))
    drop = draw(st.sampled_from([None, None, "acc_y", "t"]))
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
        return
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
    if n == 1:
        try:
            read_recording(p)
        except InputError as exc:
            assert "at least 2" in str(exc)
        return
    back = read_recording(p)
    np.testing.assert_array_equal(back.acc, rec.acc)
    assert abs(back.sampling_rate_hz - fs) <= 1e-6 * max(1.0, fs)
