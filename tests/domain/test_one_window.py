"""The one-window (streaming) domain check: the same numbers as the general path and as a plain reference."""

from __future__ import annotations

import dataclasses
import json
import warnings

import numpy as np
import pytest

from gaitml.models import load_model
from gaitml.models._predict import model_inputs
from gaitml.models.domain import fit_domain, window_gravity
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import train_config
from gaitml.simulate import simulate_dataset
from tests.reference.domain import reference_check

SMALL = {
    "name": "domain-one-window",
    "seed": 5,
    "data": {"source": "simulated", "simulated": {"subjects": 4, "pose": "mixed", "duration_s": 60.0}},
    "features": {"set": "all52"},
    "train": {"cross_validate": False},
}


def _general(dom, X, g):
    """The general (vectorised, masked) path on the same rows: distances, gravity_angles and the flags."""
    d = dom.distances(X)
    ok = d <= dom.distance_threshold
    if not dom.gravity_check:
        return {"distance": d, "gravity_angle_rad": np.full(len(d), np.nan), "in_domain": ok}
    a = dom.gravity_angles(g)
    return {"distance": d, "gravity_angle_rad": a, "in_domain": ok & (a <= dom.gravity_threshold_rad)}


def _one_by_one(dom, X, G):
    rows = [dom.check(X[i : i + 1], None if G is None else G[i : i + 1]) for i in range(len(X))]
    return {k: np.concatenate([r[k] for r in rows]) for k in ("distance", "gravity_angle_rad", "in_domain")}


def _assert_same(one, general):
    """Bit for bit: the one-window path does the general path's arithmetic."""
    for k in ("distance", "gravity_angle_rad", "in_domain"):
        np.testing.assert_array_equal(one[k], general[k], err_msg=k)
    assert one["in_domain"].dtype == bool and one["distance"].dtype == float == one["gravity_angle_rad"].dtype


def _assert_near_reference(res, ref):
    np.testing.assert_array_equal(np.isfinite(res["distance"]), np.isfinite(ref["distance"]))
    np.testing.assert_array_equal(np.isnan(res["gravity_angle_rad"]), np.isnan(ref["gravity_angle_rad"]))
    np.testing.assert_allclose(res["distance"], ref["distance"], rtol=1e-9)
    np.testing.assert_allclose(res["gravity_angle_rad"], ref["gravity_angle_rad"], rtol=0, atol=1e-9)


@pytest.fixture(scope="module")
def synthetic():
    rng = np.random.default_rng(7)
    groups = np.repeat(np.arange(6), 60).astype(str)
    y = np.tile(["a", "b", "c"], 120)
    X = rng.normal(0, 1, (360, 8)) + (y == "b")[:, None] * 3.0 + 50.0  # an offset, as raw features have
    grav = np.tile([0.0, 0.3, 1.0], (360, 1)) + rng.normal(0, 0.05, (360, 3))
    grav /= np.linalg.norm(grav, axis=1, keepdims=True)
    return fit_domain(X, y, groups, grav, feature_names=list("abcdefgh"), feature_set="all52", frame="phone", seed=2), X, grav


def test_random_rows_equal_the_general_path_and_the_reference(synthetic):
    dom, X, grav = synthetic
    rng = np.random.default_rng(11)
    Xt = X[:200] + rng.normal(0, 0.6, (200, 8))
    Gt = grav[:200] + rng.normal(0, 0.06, (200, 3))
    Gt /= np.linalg.norm(Gt, axis=1, keepdims=True)
    assert all(dom._check_one(Xt[i : i + 1], Gt[i : i + 1]) is not None for i in range(200))  # the short path answers
    one = _one_by_one(dom, Xt, Gt)
    _assert_same(one, _one_by_one_general(dom, Xt, Gt))
    _assert_near_reference(one, reference_check(dom, Xt, Gt))
    batch = dom.check(Xt, Gt)
    # the batch (at least 64 rows) takes its distances in float32 and recomputes in float64 where a flag is at stake
    np.testing.assert_allclose(one["distance"], batch["distance"], rtol=1e-6)
    np.testing.assert_array_equal(one["distance"] <= dom.distance_threshold, batch["distance"] <= dom.distance_threshold)
    # arccos near 0 magnifies the last bit of the cosine (the batch product sums in another order): absolute 1e-12 rad
    np.testing.assert_allclose(one["gravity_angle_rad"], batch["gravity_angle_rad"], rtol=0, atol=1e-12)
    assert 0.1 < one["in_domain"].mean() < 0.95  # both outcomes occur


def _one_by_one_general(dom, X, G):
    rows = [_general(dom, X[i : i + 1], G[i : i + 1]) for i in range(len(X))]
    return {k: np.concatenate([r[k] for r in rows]) for k in ("distance", "gravity_angle_rad", "in_domain")}


def test_boundaries_non_finite_and_odd_gravity_as_before(synthetic):
    dom, X, grav = synthetic
    x, g = X[5:6] + 0.3, grav[5:6] + [[0.02, -0.01, 0.0]]
    g /= np.linalg.norm(g)
    d, a = dom.distances(x)[0], dom.gravity_angles(g)[0]
    assert d > 0 and a > 0
    # exactly at either threshold: in domain; one ulp under it: out, on both paths
    for dt, gt, expect in [(d, a, True), (np.nextafter(d, 0), a, False), (d, np.nextafter(a, 0), False)]:
        at = dataclasses.replace(dom, distance_threshold=float(dt), gravity_threshold_rad=float(gt))
        assert at._check_one(x, g) is not None
        assert bool(at.check(x, g)["in_domain"][0]) is expect
        assert bool(at.check(np.repeat(x, 2, axis=0), np.repeat(g, 2, axis=0))["in_domain"][0]) is expect
    cases = {
        "nan feature": (np.where(np.arange(8) == 3, np.nan, x), g),
        "inf feature": (np.where(np.arange(8) == 0, np.inf, x), g),
        "-inf feature": (np.where(np.arange(8) == 7, -np.inf, x), g),
        "overflowing feature": (np.where(np.arange(8) == 2, 1e300, x), g),
        "nan gravity": (x, np.full((1, 3), np.nan)),
        "inf gravity": (x, np.array([[np.inf, 0.0, 1.0]])),
        "nan in gravity": (x, np.array([[0.1, np.nan, 0.9]])),  # a NaN the magnitude test may let through
        "nan and inf in gravity": (x, np.array([[0.0, np.nan, -np.inf]])),
        "zero-length gravity": (x, np.zeros((1, 3))),
        "gravity as a flat vector": (x, g[0]),
        "unnormalised gravity": (x, 9.81 * g),
    }
    for name, (xc, gc) in cases.items():
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # neither path warns (as before)
            one = dom.check(xc, gc)
            _assert_same(one, _general(dom, xc, gc))
        if name != "overflowing feature":  # the plain quadratic form overflows there; the check says inf
            _assert_near_reference(one, reference_check(dom, xc, gc))
        else:
            assert np.isinf(one["distance"][0])
        if name.endswith("feature") or "nan" in name or "inf" in name:
            assert not one["in_domain"][0], name
    assert np.isinf(dom.check(cases["nan feature"][0], g)["distance"][0])
    assert np.isnan(dom.check(x, cases["nan gravity"][1])["gravity_angle_rad"][0])
    assert dom.check(x, np.zeros(3))["gravity_angle_rad"][0] == pytest.approx(np.pi / 2)  # no direction: orthogonal to all
    with pytest.raises(Exception, match="gravity"):
        dom.check(x)  # gravity needed: the same error as before
    with pytest.raises(Exception, match="takes 8 features"):
        dom.check(x[:, :5], g)
    no_dirs = dataclasses.replace(dom, arrays={**dom.arrays, "gravity_dirs": np.zeros((0, 3))})
    res = no_dirs.check(x, g)
    assert np.isnan(res["gravity_angle_rad"][0]) and not res["in_domain"][0]
    unchecked = dataclasses.replace(dom, gravity_check=False)
    res = unchecked.check(x)
    assert np.isnan(res["gravity_angle_rad"][0]) and res["distance"][0] == d


@pytest.fixture(scope="module")
def sim_model(tmp_path_factory):
    out = tmp_path_factory.mktemp("one-window") / "m"
    train_config(parse_config(json.loads(json.dumps(SMALL))), out_dir=out, progress=False)
    return load_model(out)


def test_windows_of_a_simulated_recording(sim_model):
    """Every window of a new walker (and of a scaled, upside-down copy), one at a time = general path = reference."""
    from gaitml.models._predict import _windows_for

    rec = simulate_dataset(n_subjects=1, duration_s=45.0, pose="mixed", seed=99, sampling_rate_hz=sim_model.sampling_rate_hz)[0]
    dom = sim_model.domain
    for r in (rec, rec.replace(acc=-1.5 * rec.acc, check_units=False)):
        w = _windows_for(r, sim_model.length_s, sim_model.overlap)
        X = model_inputs(sim_model, r, w)
        length = int(round(sim_model.length_s * sim_model.sampling_rate_hz))
        G = window_gravity(r.acc, w["start"].to_numpy(), length)
        assert all(dom._check_one(X[i : i + 1], G[i : i + 1]) is not None for i in range(len(X)))  # the short path answers
        one = _one_by_one(dom, X, G)
        _assert_same(one, _one_by_one_general(dom, X, G))
        _assert_near_reference(one, reference_check(dom, X, G))
        np.testing.assert_array_equal(one["in_domain"], dom.check(X, G)["in_domain"])
    assert dom.gravity_check and len(X) > 50
