"""The batch domain check's fast paths give the numbers and flags of the plain computation.

``gaitml predict`` of a gyroscope model (``all52+gyro``, whose record has the
orientation-dynamics part) takes the feature distance in column blocks of the
triangular Cholesky factors (:meth:`DomainModel._certified_distances`) and the window
gravity from the phone-frame feature means (:func:`feature_gravity`). Both are the
same sums in another order than the plain computation (one product with the stacked
factors, gravity from prefix sums; ``tests/reference/domain.py``): on a simulated
recording the flags are the same and the numbers agree to rounding.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gaitml.models import load_model, predict_recording
from gaitml.models._predict import _windows_for, foot_placement, model_inputs
from gaitml.models.domain import _BLOCKED_MIN_ROWS, ACC_MEAN_FEATURES, feature_gravity, orientation_dynamics, running_median, window_gravity
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import train_config
from gaitml.simulate import simulate_dataset
from tests.reference.domain import (
    dynamics_distances_loop,
    reference_check,
    span_median_loop,
    stacked_distances,
    stacked_dynamics_distances,
)

GYRO = {
    "name": "domain-check-cost",
    "seed": 3,
    "data": {"source": "simulated", "simulated": {"subjects": 3, "pose": "mixed", "duration_s": 40.0}},
    "features": {"set": "all52+gyro"},
    "train": {"cross_validate": False},
}


@pytest.fixture(scope="module")
def gyro_model(tmp_path_factory):
    out = tmp_path_factory.mktemp("check-cost") / "m"
    train_config(parse_config(json.loads(json.dumps(GYRO))), out_dir=out, progress=False)
    model = load_model(out)
    assert model.domain.dynamics is not None and model.domain.gravity_check and model.domain.frame == "phone"
    return model


@pytest.fixture(scope="module")
def walker(gyro_model):
    return simulate_dataset(n_subjects=1, duration_s=120.0, pose="mixed", seed=77, sampling_rate_hz=gyro_model.sampling_rate_hz)[0]


def _before(model, rec) -> dict[str, np.ndarray]:
    """The domain columns as computed before: stacked-factor distances, prefix-sum gravity, the nearest angle, the span median."""
    dom = model.domain
    w = _windows_for(rec, model.length_s, model.overlap)
    starts = w["start"].to_numpy(np.int64)
    length = int(round(model.length_s * model.sampling_rate_hz))
    X = model_inputs(model, rec, w)
    d = stacked_distances(dom, X)
    G = window_gravity(rec.acc, starts, length)
    cos = np.where(np.isfinite(G).all(axis=1)[:, None], G, 0.0) @ dom.arrays["gravity_dirs"].T
    ang = np.arccos(np.clip(cos.max(axis=1), -1.0, 1.0))
    ang[~np.isfinite(G).all(axis=1)] = np.nan
    rows = dom.dynamics_rows(len(starts))  # the descriptors of every dynamics_every-th window, as predict computes them
    q = orientation_dynamics(rec.acc, rec.gyr, starts[rows], starts[rows] + length, rec.sampling_rate_hz)
    per_window = np.full(len(starts), np.nan)
    per_window[rows] = stacked_dynamics_distances(dom, q)  # standardised first, then the stacked factors
    dyn = span_median_loop(per_window, dom.dynamics["span"], dom.dynamics_every)  # nanmedian of each span's grid windows
    ok = (d <= dom.distance_threshold) & (ang <= dom.gravity_threshold_rad) & (dyn <= dom.dynamics["threshold"])
    ok &= ~foot_placement(model, rec, w)  # predict adds the fixed foot-placement rule to the record's check
    return {"in_domain": ok, "domain_distance": d, "gravity_angle_deg": np.degrees(ang), "dynamics_distance": dyn}


@pytest.mark.parametrize("case", ["as recorded", "upside down and scaled"])
def test_predict_flags_equal_the_previous_computation(gyro_model, walker, case):
    rec = walker if case == "as recorded" else walker.replace(acc=-1.5 * walker.acc, check_units=False)
    t = predict_recording(gyro_model, rec)
    ref = _before(gyro_model, rec)
    assert len(t) > 2 * _BLOCKED_MIN_ROWS  # the batch (column-block) path
    np.testing.assert_array_equal(t["in_domain"].astype(bool).to_numpy(), ref["in_domain"])
    # float32 distances (about 1e-7 relative), float64 where a window lies near the threshold: the flags are equal above
    np.testing.assert_allclose(t["domain_distance"].to_numpy(float), ref["domain_distance"], rtol=1e-6)
    # arccos near 0 magnifies the last bit of a cosine: absolute 1e-9 deg (thresholds are degrees)
    np.testing.assert_allclose(t["gravity_angle_deg"].to_numpy(float), ref["gravity_angle_deg"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(t["dynamics_distance"].to_numpy(float), ref["dynamics_distance"], rtol=1e-12)  # standardised in the product
    flagged = 1.0 - ref["in_domain"].mean()
    assert (flagged < 0.5) if case == "as recorded" else (flagged == 1.0)  # both outcomes are exercised


def _exact(dom, X):
    """The float64 feature distances by the plain reference (one class at a time)."""
    from gaitml.models.domain import _min_mahalanobis

    return _min_mahalanobis((X - dom.arrays["center"]) / dom.arrays["scale"], dom.arrays["class_means"], dom.arrays["class_precisions"])


def test_blocked_distances_equal_the_one_product_and_the_per_window_reference(gyro_model, walker):
    dom = gyro_model.domain
    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    X = model_inputs(gyro_model, walker, w)
    rng = np.random.default_rng(5)
    X = np.vstack([X, X[:40] + rng.normal(0, 3, (40, X.shape[1])) * X.std(axis=0)])  # and far windows
    X[7, 3] = np.nan
    X[11, 50] = -np.inf
    no_gravity = dataclasses.replace(dom, gravity_check=False)  # the reference's distances alone
    for n in (_BLOCKED_MIN_ROWS - 1, _BLOCKED_MIN_ROWS, len(X)):  # the one product below the limit, the blocks from it on
        d = dom.distances(X[:n])
        before = stacked_distances(dom, X[:n])
        np.testing.assert_array_equal(np.isinf(d), np.isinf(before))
        fin = np.isfinite(before)
        # float32 from 64 rows on (float64 near the threshold): the flags of the float64 distances, the numbers to 1e-6
        np.testing.assert_allclose(d[fin], before[fin], rtol=1e-12 if n < _BLOCKED_MIN_ROWS else 1e-6)
        np.testing.assert_array_equal(d <= dom.distance_threshold, before <= dom.distance_threshold)
        np.testing.assert_allclose(d[fin], reference_check(no_gravity, X[:n][fin])["distance"], rtol=1e-6)
        Xf = np.where(np.isfinite(X[:n]), X[:n], 0.0)
        exact = _exact(dom, Xf)  # the plain reference the float32 path recomputes with near the threshold
        np.testing.assert_allclose(exact[fin], before[fin], rtol=1e-12)
        np.testing.assert_allclose(exact[fin], reference_check(no_gravity, X[:n][fin])["distance"], rtol=1e-9)
    assert np.isinf(d[[7, 11]]).all() and fin.sum() == len(X) - 2
    # a sum that overflows in the blocks: the one product answers, as before
    huge = np.where(np.arange(X.shape[1]) == 5, 1e250, X[100:200])
    with np.errstate(over="ignore", invalid="ignore"):
        np.testing.assert_array_equal(dom.distances(huge), dom._stacked_distances((huge - dom.arrays["center"]) / dom.arrays["scale"]))


def test_feature_gravity_is_window_gravity(gyro_model, walker):
    dom = gyro_model.domain
    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    starts = w["start"].to_numpy(np.int64)
    X = model_inputs(gyro_model, walker, w)
    G = feature_gravity(X, dom.feature_names)
    np.testing.assert_allclose(G, window_gravity(walker.acc, starts, 75), rtol=0, atol=1e-12)
    # a window without a direction (mean nearly zero): NaN, as window_gravity says
    X0 = X.copy()
    X0[3, [dom.feature_names.index(n) for n in ACC_MEAN_FEATURES]] = [1e-8, 0.0, -1e-8]
    assert np.isnan(feature_gravity(X0, dom.feature_names)[3]).all() and np.isfinite(feature_gravity(X0, dom.feature_names)[4]).all()
    # no mean columns (paper34 has none) or a non-finite mean: None, the caller uses window_gravity
    assert feature_gravity(X[:, 3:], dom.feature_names[3:]) is None
    X0[5, dom.feature_names.index("acc_y__mean")] = np.inf
    assert feature_gravity(X0, dom.feature_names) is None


def test_a_gravity_frame_record_reads_the_recording_not_the_features(gyro_model, walker):
    """A record whose frame is not the phone's never takes the gravity from the features (their x, y means are zero there)."""
    dom = gyro_model.domain
    odd = dataclasses.replace(gyro_model, domain=dataclasses.replace(dom, frame="gravity"))  # gravity_check kept on
    from gaitml.models._predict import domain_columns

    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    cols = domain_columns(odd, walker, w)  # features recomputed in the record's frame
    G = window_gravity(walker.acc, w["start"].to_numpy(np.int64), 75)
    np.testing.assert_allclose(cols["gravity_angle_deg"], np.degrees(dom.gravity_angles(G)), rtol=0, atol=1e-9)


def test_dynamics_distances_equal_the_stacked_product_and_the_per_window_loop(gyro_model, walker):
    """The dynamics distance with the standardisation and offsets inside its one product: the same numbers to rounding."""
    dom = gyro_model.domain
    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    starts = w["start"].to_numpy(np.int64)
    Q = orientation_dynamics(walker.acc, walker.gyr, starts, starts + 75, walker.sampling_rate_hz)
    rng = np.random.default_rng(8)
    Q = np.vstack([Q, Q[:30] + rng.normal(0, 4, (30, Q.shape[1])) * Q.std(axis=0)])  # and far windows
    Q[4, 2] = np.nan
    Q[9, 0] = np.inf
    d = dom.dynamics_distances(Q)
    before = stacked_dynamics_distances(dom, Q)
    np.testing.assert_array_equal(np.isinf(d), np.isinf(before))
    assert np.isinf(d[[4, 9]]).all() and np.isfinite(d).sum() == len(Q) - 2
    fin = np.isfinite(before)
    np.testing.assert_allclose(d[fin], before[fin], rtol=1e-12)
    np.testing.assert_allclose(d[fin], dynamics_distances_loop(dom, Q)[fin], rtol=1e-9)
    # the flags the threshold gives are those of the standardised product
    np.testing.assert_array_equal(d <= dom.dynamics["threshold"], before <= dom.dynamics["threshold"])
    # an overflowing input is out of domain (inf), never a NaN the span median would skip
    with np.errstate(over="ignore", invalid="ignore"):
        huge = dom.dynamics_distances(np.where(np.arange(Q.shape[1]) == 3, 1e300, Q[:5]))
    assert np.isinf(huge).all()


@pytest.mark.parametrize("span", [1, 2, 3, 10, 20, 40, 60])
def test_running_median_of_one_recording_without_nan_is_the_span_loop(span):
    """The check's running median (one recording, no NaN: the sorted strided spans) against nanmedian of each span, any span."""
    rng = np.random.default_rng(span)
    for n in (0, 1, span - 1, span, span + 1, 3 * span + 7, 400):
        d = rng.gamma(2.0, 2.0, max(n, 0))
        if n > 5:
            d[[2, n // 2]] = np.inf  # a non-finite descriptor gives inf: a value, not a gap
            d[n // 3] = d[n // 3 + 1]  # ties
        got = running_median(d, span)
        np.testing.assert_array_equal(got, span_median_loop(d, span), err_msg=f"span {span}, n {n}")
        # the general path (rows of several recordings, NaN skipped) gives the same numbers for one recording
        np.testing.assert_array_equal(got, running_median(d, span, np.zeros(len(d))), err_msg=f"span {span}, n {n}")
    d = rng.gamma(2.0, 2.0, 3 * span + 7)
    d[span // 2] = np.nan  # a NaN: the general path, still the nanmedian of each span
    np.testing.assert_array_equal(running_median(d, span), span_median_loop(d, span))


def test_descriptors_of_tiling_windows_equal_the_gathered_samples(walker):
    """The check's grid (windows tiling the kept samples: one slice per signal) gives the descriptors of the general gather, bit for bit."""
    fs = walker.sampling_rate_hz
    starts = np.arange(0, len(walker.acc) - 75, 76)  # every second 1.5 s window at 50 Hz: 38 kept samples each, back to back
    tiled = orientation_dynamics(walker.acc, walker.gyr, starts, starts + 75, fs)
    odd = np.r_[starts, 1]  # one window off the grid: the samples are gathered by index
    np.testing.assert_array_equal(tiled, orientation_dynamics(walker.acc, walker.gyr, odd, odd + 75, fs)[:-1])
    # one window alone (its slice): the same up to the last bit of a BLAS sum of another length
    np.testing.assert_allclose(
        tiled[3:4], orientation_dynamics(walker.acc, walker.gyr, starts[3:4], starts[3:4] + 75, fs), rtol=1e-12, atol=1e-15
    )
    assert np.isfinite(tiled).all() and tiled.shape == (len(starts), 13)


def test_the_batch_check_runs_on_one_blas_thread_and_restores_the_count(gyro_model, walker):
    """The batch check's products run with one BLAS thread; the caller's thread count is back afterwards, also after an error."""
    from threadpoolctl import threadpool_info

    from gaitml.errors import ModelError
    from gaitml.models import domain as D

    def counts():
        return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]

    before = counts()
    seen = []
    real = D.DomainModel.distances

    def spy(self, X):
        seen.append(counts())
        return real(self, X)

    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    X = model_inputs(gyro_model, walker, w)
    try:
        D.DomainModel.distances = spy
        gyro_model.domain.check(X, feature_gravity(X, gyro_model.domain.feature_names))
        with pytest.raises(ModelError, match="gravity"):
            gyro_model.domain.check(X, None)  # an error inside: the count is restored all the same
        with D.one_blas_thread(), D.one_blas_thread():  # nested: restored once, at the outer exit
            assert set(counts()) <= {1}
        assert counts() == before
    finally:
        D.DomainModel.distances = real
    assert seen and all(set(c) <= {1} for c in seen)
    assert counts() == before


def test_float32_distances_give_the_float64_flags_at_any_threshold(gyro_model, walker):
    """Thresholds placed on the windows' own distances: every flag equals the float64 one; the windows near it get float64 numbers."""
    dom = gyro_model.domain
    w = _windows_for(walker, gyro_model.length_s, gyro_model.overlap)
    X = model_inputs(gyro_model, walker, w)
    exact = _exact(dom, X)  # float64
    far = dom.distances(X)
    np.testing.assert_allclose(far, exact, rtol=1e-6)
    assert np.abs(far / exact - 1).max() > 1e-12  # the float32 products do answer away from the threshold
    picks = np.argsort(exact)[[0, len(X) // 4, len(X) // 2, 3 * len(X) // 4, -1]]
    for i in picks:
        # thresholds 1e-12 .. 1e-7 from a window's distance: far above float64 rounding (about 1e-16; a product of
        # another number of rows can move a distance by an ulp, as the one-window path does), far below float32's
        for thr in exact[i] * np.array([1 - 1e-7, 1 - 1e-12, 1 + 1e-12, 1 + 1e-7]):
            at = dataclasses.replace(dom, distance_threshold=float(thr))
            d = at.distances(X)
            np.testing.assert_array_equal(d <= thr, exact <= thr, err_msg=f"threshold {thr!r} at window {i}")
            assert abs(d[i] / exact[i] - 1) < 1e-14  # near the threshold: recomputed in float64
            np.testing.assert_array_equal(at.check(X, feature_gravity(X, dom.feature_names))["distance"] <= thr, exact <= thr)
