"""Batch == streaming == plain per-window reference (1e-9), and property tests."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from gaitml.errors import InputError
from gaitml.features import StreamingFeatureExtractor, extract_features, feature_names, features_from_arrays, make_windows
from gaitml.features._catalogue import MODE_BIN_WIDTH
from gaitml.recording import Recording
from tests.reference.features import reference_features

TOL = {"rtol": 1e-9, "atol": 1e-9}


def _gait_like(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 50.0
    acc = np.column_stack([np.sin(2 * np.pi * 1.8 * t), 0.5 * np.cos(2 * np.pi * 0.9 * t), 9.8 + 2 * np.sin(2 * np.pi * 1.8 * t + 0.3)])
    acc = acc + rng.normal(0, 0.4, (n, 3))
    gyr = rng.normal(0, 0.8, (n, 3))
    return acc, gyr


@pytest.mark.parametrize("subset", ["all52", "paper34", "all52+gyro", "all52+fwd", "all52+gyro+fwd", "all52+gyro+fwdface"])
@pytest.mark.parametrize(("length_s", "overlap"), [(1.5, 0.5), (0.5, 0.0), (2.0, 0.75)])
def test_batch_equals_streaming_equals_reference(subset, length_s, overlap):
    acc, gyr = _gait_like(1500, seed=3)
    rec = Recording.from_arrays(acc, 50.0, gyr=gyr)
    batch = extract_features(rec, subset=subset, length_s=length_s, overlap=overlap)
    assert list(batch.columns) == feature_names(subset)
    win = make_windows(rec, length_s, overlap, min_label_fraction=0.0)
    ref = reference_features(acc, gyr, win["start"].to_numpy(), win.attrs["length_samples"], subset)
    np.testing.assert_allclose(batch.to_numpy(), ref, **TOL)
    # streaming with irregular chunk sizes, including empty and single-sample chunks
    ext = StreamingFeatureExtractor(50.0, length_s, overlap, subset)
    assert ext.feature_names_ == feature_names(subset)
    rng = np.random.default_rng(1)
    rows, starts, i = [], [], 0
    while i < len(acc):
        k = int(rng.choice([0, 1, 7, 40, 113]))
        out = ext.push(acc[i : i + k], gyr[i : i + k] if "gyro" in subset else None)
        rows.append(out)
        starts.append(ext.last_starts_)
        i += k
    stream = np.concatenate(rows)
    np.testing.assert_allclose(stream, batch.to_numpy(), **TOL)
    np.testing.assert_array_equal(np.concatenate(starts), win["start"].to_numpy())
    assert ext.n_windows_ == len(batch) and ext.n_samples_ == len(acc)


def test_streaming_single_samples_and_reset():
    acc, _ = _gait_like(300, seed=4)
    ext = StreamingFeatureExtractor(50.0)
    rows = [ext.push(a) for a in acc]  # one (3,) sample at a time
    got = np.concatenate([r for r in rows if len(r)])
    want = features_from_arrays(acc, None, 50.0, make_windows(Recording.from_arrays(acc, 50.0), min_label_fraction=0)["start"], 75)
    np.testing.assert_allclose(got, want, **TOL)
    ext.reset()
    assert ext.n_windows_ == 0 and len(ext.push(acc[:74])) == 0 and len(ext.push(acc[74:75])) == 1


def test_streaming_needs_gyro():
    ext = StreamingFeatureExtractor(50.0, subset="all52+gyro")
    with pytest.raises(InputError, match="gyroscope"):
        ext.push(np.zeros((10, 3)))


finite = st.floats(-40, 40, allow_nan=False, allow_infinity=False)


@settings(max_examples=40, deadline=None)
@given(
    window=hnp.arrays(np.float64, (20, 3), elements=finite),
    before=st.integers(0, 30),
    after=st.integers(0, 30),
    seed=st.integers(0, 2**16),
)
def test_features_invariant_to_window_position(window, before, after, seed):
    """A window's features depend on its own samples only, wherever it sits."""
    rng = np.random.default_rng(seed)
    sig = np.concatenate([rng.normal(0, 5, (before, 3)), window, rng.normal(0, 5, (after, 3))])
    alone = features_from_arrays(window, None, 50.0, [0], 20)
    inside = features_from_arrays(sig, None, 50.0, [before], 20)
    np.testing.assert_allclose(inside, alone, rtol=1e-12, atol=1e-12)
    assert np.all(np.isfinite(alone))


@settings(max_examples=30, deadline=None)
@given(sig=hnp.arrays(np.float64, st.tuples(st.integers(10, 60), st.just(3)), elements=finite), length=st.integers(4, 10))
@example(sig=np.where(np.arange(30).reshape(10, 3) == 0, 0.0, 5.96046448e-08), length=5)  # ill-conditioned acc_mag skew
@example(sig=np.where(np.arange(30).reshape(10, 3) == 6, 0.15, 0.0), length=4)  # acc_mag's moving average on a bin edge
def test_vectorised_equals_reference_on_random_signals(sig, length):
    starts = np.arange(0, len(sig) - length + 1, max(1, length // 2))
    got = features_from_arrays(sig, None, 50.0, starts, length)
    want = reference_features(sig, None, starts, length)
    mode_cols = [i for i, n in enumerate(feature_names()) if n.endswith("__mode")]
    other = [i for i in range(52) if i not in mode_cols]
    # moments of near-constant random windows are ill-conditioned: compare relative to scale, and
    # allow skewness and kurtosis the rounding of centring (eps * |mean| / std of their channel,
    # e.g. acc_mag = |a| - g of a window of values near 6e-8 has |mean| / std ~ 5e8)
    names = feature_names()
    scale = 1.0 + np.abs(want[:, other])
    tol = 1e-7 * scale
    for j, col in enumerate(other):
        channel, stat = names[col].split("__")
        if stat in ("skew", "kurt"):
            mean = want[:, names.index(f"{channel}__mean")]
            std = np.sqrt(want[:, names.index(f"{channel}__var")])
            with np.errstate(divide="ignore", invalid="ignore"):
                cond = np.where(std > 0, np.abs(mean) / std, 0.0)
            tol[:, j] += 1e3 * np.finfo(float).eps * cond * scale[:, j]
    assert np.all(np.abs(got[:, other] - want[:, other]) <= tol)
    # the mode is exact, except that a value within rounding of a bin edge (e.g. a 3-sample moving average
    # landing on k * w - w / 2) may fall in the neighbouring bin: then the two differ by exactly one bin width
    width = MODE_BIN_WIDTH["acc"]
    diff = np.abs(got[:, mode_cols] - want[:, mode_cols])
    assert np.all(np.isclose(diff, 0.0, atol=1e-9) | np.isclose(diff, width, rtol=1e-9, atol=1e-9)), diff
    assert np.mean(np.isclose(diff, 0.0, atol=1e-9)) >= 0.5  # edge ties are rare, not the rule


@settings(max_examples=30, deadline=None)
@given(shift=st.floats(-5, 5), scale=st.floats(0.2, 5))
def test_affine_invariants(shift, scale):
    """var scales by a^2, corr/skew/kurt are invariant under x -> a x + b (a > 0)."""
    acc, _ = _gait_like(200, seed=9)
    acc2 = acc.copy()
    acc2[:, 0] = scale * acc[:, 0] + shift
    names = feature_names()
    f1 = dict(zip(names, features_from_arrays(acc, None, 50.0, [10, 80], 75).T, strict=True))
    f2 = dict(zip(names, features_from_arrays(acc2, None, 50.0, [10, 80], 75).T, strict=True))
    np.testing.assert_allclose(f2["acc_x__var"], scale**2 * f1["acc_x__var"], rtol=1e-9)
    np.testing.assert_allclose(f2["acc_x__mean"], scale * f1["acc_x__mean"] + shift, rtol=1e-9, atol=1e-9)
    for n in ("acc_xy__corr", "acc_xz__corr", "acc_x__skew", "acc_x__kurt"):
        np.testing.assert_allclose(f2[n], f1[n], rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(f2["acc_x__f1"], scale**2 * f1["acc_x__f1"], rtol=1e-9)
    np.testing.assert_allclose(f2["acc_x__m4"], scale**2 * f1["acc_x__m4"], rtol=1e-9)


def test_bad_inputs():
    acc, _ = _gait_like(130)
    rec = Recording.from_arrays(acc, 50.0)
    with pytest.raises(InputError, match="gyroscope"):
        extract_features(rec, subset="all52+gyro")
    with pytest.raises(InputError, match="unknown feature subset"):
        extract_features(rec, subset="all53")
    with pytest.raises(InputError, match="window"):
        features_from_arrays(acc, None, 50.0, [120], 20)
    with pytest.raises(InputError, match=r"75 samples \(1.5 s"):
        extract_features(rec.slice(0, 50))
    w = make_windows(rec, min_label_fraction=0)
    w.loc[0, "end"] += 1
    with pytest.raises(InputError, match="same length"):
        extract_features(rec, w)
    assert extract_features(rec, subset="all").shape == (2, 52)


@pytest.mark.parametrize("subset", ["all52", "paper34", "all52+gyro", "all52+gyro+fwd"])
@pytest.mark.parametrize(("length_s", "overlap"), [(1.5, 0.5), (0.5, 0.0)])
def test_gravity_frame_batch_equals_streaming_equals_reference(subset, length_s, overlap):
    """The gravity frame (issue 12): batch == streaming == the per-window loop of tests/reference/frame.py."""
    from tests.reference.frame import reference_gravity_features

    acc, gyr = _gait_like(1500, seed=5)
    rec = Recording.from_arrays(acc, 50.0, gyr=gyr)
    batch = extract_features(rec, subset=subset, length_s=length_s, overlap=overlap, frame="gravity").to_numpy()
    win = make_windows(rec, length_s, overlap, min_label_fraction=0.0)
    length = win.attrs["length_samples"]
    full = reference_gravity_features(acc, gyr, win["start"].to_numpy(), length, "all52+gyro")
    if subset.endswith("+fwd"):  # the forward vector in each window's gravity frame
        from tests.reference.features import reference_forward
        from tests.reference.frame import reference_rotation

        fwd = [reference_rotation(acc[s : s + length]) @ reference_forward(acc[s : s + length], 50.0) for s in win["start"]]
        full = np.column_stack([full, np.asarray(fwd)])
    all_names = feature_names("all52+gyro") + ["acc_x__fwd", "acc_y__fwd", "acc_z__fwd"]
    want = full[:, [all_names.index(n) for n in feature_names(subset)]]
    names = feature_names(subset)
    exact = [i for i, n in enumerate(names) if not n.endswith("__mode")]
    np.testing.assert_allclose(batch[:, exact], want[:, exact], rtol=1e-7, atol=1e-7)
    ext = StreamingFeatureExtractor(50.0, length_s, overlap, subset, frame="gravity")
    rng = np.random.default_rng(4)
    rows, i = [], 0
    while i < len(acc):
        k = int(rng.choice([0, 1, 7, 40, 113]))
        rows.append(ext.push(acc[i : i + k], gyr[i : i + k] if "gyro" in subset else None))
        i += k
    np.testing.assert_allclose(np.concatenate(rows), batch, **TOL)
