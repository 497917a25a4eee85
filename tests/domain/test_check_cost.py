"""The cheaper batch domain check (issue 12 speed) computes what it computed before.

``gaitml predict`` of a gyroscope model (``all52+gyro``, whose record has the
orientation-dynamics part) now takes the feature distance in column blocks of the
triangular Cholesky factors (:meth:`DomainModel._blocked_distances`) and the window
gravity from the phone-frame feature means (:func:`feature_gravity`). Both are the
same sums in another order: on a simulated recording the flags are those of the
previous computation (one product with the stacked factors, gravity from prefix sums;
``tests/reference/domain.py``) and the numbers agree to rounding.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gaitml.experiments.config import parse_config
from gaitml.experiments.runner import train_config
from gaitml.models import load_model, predict_recording
from gaitml.models._predict import _windows_for, model_inputs
from gaitml.models.domain import _BLOCKED_MIN_ROWS, ACC_MEAN_FEATURES, feature_gravity, span_medians, window_gravity
from gaitml.simulate import simulate_dataset
from tests.reference.domain import reference_check, stacked_distances

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
    from gaitml.models.domain import orientation_dynamics

    rows = dom.dynamics_rows(len(starts))  # the descriptors of every dynamics_every-th window, as predict computes them
    q = orientation_dynamics(rec.acc, rec.gyr, starts[rows], starts[rows] + length, rec.sampling_rate_hz)
    per_window = np.full(len(starts), np.nan)
    per_window[rows] = dom.dynamics_distances(q)
    dyn = span_medians(per_window, dom.dynamics["span"], dom.dynamics_every)  # reads the grid rows only
    ok = (d <= dom.distance_threshold) & (ang <= dom.gravity_threshold_rad) & (dyn <= dom.dynamics["threshold"])
    return {"in_domain": ok, "domain_distance": d, "gravity_angle_deg": np.degrees(ang), "dynamics_distance": dyn}


@pytest.mark.parametrize("case", ["as recorded", "upside down and scaled"])
def test_predict_flags_equal_the_previous_computation(gyro_model, walker, case):
    rec = walker if case == "as recorded" else walker.replace(acc=-1.5 * walker.acc, check_units=False)
    t = predict_recording(gyro_model, rec)
    ref = _before(gyro_model, rec)
    assert len(t) > 2 * _BLOCKED_MIN_ROWS  # the batch (column-block) path
    np.testing.assert_array_equal(t["in_domain"].astype(bool).to_numpy(), ref["in_domain"])
    np.testing.assert_allclose(t["domain_distance"].to_numpy(float), ref["domain_distance"], rtol=1e-12)
    # arccos near 0 magnifies the last bit of a cosine: absolute 1e-9 deg (thresholds are degrees)
    np.testing.assert_allclose(t["gravity_angle_deg"].to_numpy(float), ref["gravity_angle_deg"], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(t["dynamics_distance"].to_numpy(float), ref["dynamics_distance"])  # that part is unchanged
    flagged = 1.0 - ref["in_domain"].mean()
    assert (flagged < 0.5) if case == "as recorded" else (flagged == 1.0)  # both outcomes are exercised


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
        np.testing.assert_allclose(d[fin], before[fin], rtol=1e-12)
        np.testing.assert_allclose(d[fin], reference_check(no_gravity, X[:n][fin])["distance"], rtol=1e-9)
    assert np.isinf(d[[7, 11]]).all() and fin.sum() == len(X) - 2
    blocks = dom._factor_blocks()
    assert len(blocks) == 4 and [b[0] for b in blocks] == [0, 26, 52, 78] and blocks[0][2].shape == (5 * 26, 104)
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
