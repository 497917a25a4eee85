"""DomainCheck: the domain check as a scikit-learn style estimator (fit(X, y, groups), check_windows, get_params)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone

from gaitml.errors import ModelError
from gaitml.models.domain import DYNAMICS_NAMES, DYNAMICS_SPAN, ChunkContext, DomainCheck, dynamics_sample_step, fit_domain

ROOT = Path(__file__).resolve().parents[2]


def _training(n_per=60, p=6, seed=3):
    """Two classes, four subjects, Gaussian features; gravity near +z; dynamics descriptors; one recording per subject."""
    rng = np.random.default_rng(seed)
    X = np.vstack([rng.normal(0, 1, (n_per, p)), rng.normal(4, 1, (n_per, p))])
    y = np.repeat(["walk", "run"], n_per)
    groups = np.tile(np.repeat(["s1", "s2", "s3", "s4"], n_per // 4), 2)
    g = rng.normal([0, 0, 1], 0.05, (2 * n_per, 3))
    g /= np.linalg.norm(g, axis=1, keepdims=True)
    Q = rng.normal(0, 1, (2 * n_per, len(DYNAMICS_NAMES)))
    return X, y, groups, g, Q


def test_parameters_are_scikit_learn_style():
    est = DomainCheck(frame="gravity", quantile=0.95)
    params = est.get_params()
    assert params["frame"] == "gravity" and params["quantile"] == 0.95 and params["dynamics_span"] == DYNAMICS_SPAN
    assert clone(est).get_params() == params
    assert not hasattr(est, "record_")  # __init__ stores parameters only


def test_fit_returns_self_and_the_record_fit_domain_gives():
    X, y, groups, g, Q = _training()
    names = [f"f{i}" for i in range(X.shape[1])]
    est = DomainCheck(feature_names=names, feature_set="toy", frame="phone", random_state=2)
    assert est.fit(X, y, groups, gravity=g, dynamics=Q, sequence=groups) is est
    ref = fit_domain(X, y, groups, g, feature_names=names, feature_set="toy", frame="phone", seed=2, dynamics=Q, sequence=groups)
    assert est.record_.to_json() == ref.to_json()
    for k, v in ref.to_arrays().items():
        np.testing.assert_array_equal(est.record_.to_arrays()[k], v, err_msg=k)
    assert est.classes_ == ["run", "walk"]


def test_check_windows_gives_per_window_distances_and_flags():
    X, y, groups, g, _ = _training()
    est = DomainCheck(feature_names=[f"f{i}" for i in range(X.shape[1])]).fit(X, y, groups, gravity=g)
    far = np.vstack([X[:5], X[:5] + 50.0])  # five training windows, five far from every class
    table = est.check_windows(far, np.vstack([g[:5], g[:5]]))
    assert isinstance(table, pd.DataFrame) and len(table) == 10
    assert list(table.columns) == ["distance", "gravity_angle_rad", "dynamics_distance", "in_domain"]
    assert table["in_domain"].iloc[5:].eq(False).all() and table["in_domain"].iloc[:5].sum() >= 4
    assert (table["distance"].iloc[5:] > table["distance"].iloc[:5].max()).all()


def test_an_unfitted_estimator_says_so():
    with pytest.raises(ModelError, match="not fitted"):
        DomainCheck().check_windows(np.zeros((1, 3)))


def test_the_chunk_context_comes_from_the_record():
    X, y, groups, g, Q = _training()
    names = [f"f{i}" for i in range(X.shape[1])]
    plain = DomainCheck(feature_names=names).fit(X, y, groups, gravity=g)
    assert plain.chunk_context(100.0) == ChunkContext(0, 1, 1)
    dyn = DomainCheck(feature_names=names, dynamics_span=12).fit(X, y, groups, gravity=g, dynamics=Q, sequence=groups)
    ctx = dyn.chunk_context(100.0)
    assert ctx == ChunkContext(11, dynamics_sample_step(100.0), dyn.record_.dynamics_every)
    assert ctx.sample_step == 4 and ctx.window_step == 2


def test_a_shipped_model_record_wraps_into_the_estimator():
    from gaitml.models import load_model

    model = load_model(ROOT / "models" / "demo")
    est = DomainCheck.from_record(model.domain)
    assert est.get_params()["frame"] == model.domain.frame and est.record_ is model.domain
    dyn = model.domain.dynamics
    assert est.chunk_context(model.sampling_rate_hz).left_windows == (0 if dyn is None else dyn["span"] - 1)
