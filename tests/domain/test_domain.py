"""The model's training domain (gaitml.models.domain): record, save/load data-only, predict/pdr flags and warnings."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.cli import main
from gaitml.commands._domain import NO_DOMAIN_WARNING
from gaitml.errors import ModelError
from gaitml.io import write_gaitml_csv
from gaitml.models import load_model, model_card, predict_recording
from gaitml.models._persist import ARRAYS_NAME, JSON_NAME, settings_sha256, sha256_file
from gaitml.models.domain import DomainModel, fit_domain, out_of_domain_fraction, window_gravity
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import train_config
from gaitml.simulate import simulate_dataset
from tests.conftest import shared

SMALL = {
    "name": "domain-test",
    "seed": 3,
    "data": {"source": "simulated", "simulated": {"subjects": 5, "pose": "mixed", "duration_s": 75.0}},
    "features": {"set": "all52+gyro"},
    "train": {"cross_validate": False},
}


def _train(tmp_path_factory, frame: str):
    raw = json.loads(json.dumps(SMALL))
    raw["features"]["frame"] = frame
    out = tmp_path_factory.mktemp(f"model-{frame}")
    train_config(parse_config(raw), out_dir=out / "m", progress=False)
    return out / "m"


@pytest.fixture(scope="module")
def phone_model(tmp_path_factory):
    return _train(tmp_path_factory, "phone")


@pytest.fixture(scope="module")
def gravity_model(tmp_path_factory):
    return _train(tmp_path_factory, "gravity")


@pytest.fixture(scope="module")
def new_subject():
    """A walker the models were not trained on (another seed)."""
    return simulate_dataset(n_subjects=1, duration_s=60.0, pose="flat", seed=404)[0]


def _cli(argv, capsys):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def _warnings(err: str) -> list[str]:
    return [ln for ln in err.splitlines() if ln.startswith("gaitml: warning:")]


# ---------------------------------------------------------------- the record itself


def test_fit_domain_flags_far_windows_and_keeps_near_ones():
    rng = np.random.default_rng(0)
    groups = np.repeat(np.arange(10), 60).astype(str)
    y = np.tile(["a", "b"], 300)
    X = rng.normal(0, 1, (600, 6)) + (y == "b")[:, None] * 4.0
    grav = np.tile([0.0, 0.2, 1.0], (600, 1)) + rng.normal(0, 0.02, (600, 3))
    grav /= np.linalg.norm(grav, axis=1, keepdims=True)
    dom = fit_domain(X, y, groups, grav, feature_names=list("uvwxyz"), feature_set="all52", frame="phone", seed=1)
    assert dom.distance_threshold >= 0.95 * dom.distance_threshold_in_sample  # iid groups: held out about equals in sample
    Xn = rng.normal(0, 1, (400, 6)) + (rng.random(400) < 0.5)[:, None] * 4.0
    gn = grav[:400]
    near = dom.check(Xn, gn)["in_domain"]
    assert near.mean() >= 0.9
    far = dom.check(Xn + 12.0, gn)["in_domain"]
    assert far.mean() == 0.0
    tipped = dom.check(Xn, -gn)["in_domain"]  # phone upside down: gravity check alone
    assert tipped.mean() == 0.0
    # data-only round trip
    back = DomainModel.from_json(json.loads(json.dumps(dom.to_json())), dom.to_arrays())
    np.testing.assert_array_equal(back.check(Xn, gn)["in_domain"], near)
    with pytest.raises(ModelError, match="retrain"):
        DomainModel.from_json(dom.to_json(), {k: v for k, v in dom.to_arrays().items() if "center" not in k})


def test_one_window_checks_equal_the_batch_check():
    """The streaming path checks one window at a time: same flags and distances as the batch, non-finite input out of domain."""
    rng = np.random.default_rng(3)
    groups = np.repeat(np.arange(6), 50).astype(str)
    y = np.tile(["a", "b", "c"], 100)
    X = rng.normal(0, 1, (300, 5)) + (y == "b")[:, None] * 3.0
    grav = np.tile([0.0, 0.1, 1.0], (300, 1)) + rng.normal(0, 0.03, (300, 3))
    grav /= np.linalg.norm(grav, axis=1, keepdims=True)
    dom = fit_domain(X, y, groups, grav, feature_names=list("uvwxy"), feature_set="all52", frame="phone", seed=0)
    Xt, gt = X[:40] + rng.normal(0, 2, (40, 5)), grav[:40].copy()
    Xt[3, 2], Xt[7, 0], gt[11] = np.nan, np.inf, np.nan
    batch = dom.check(Xt, gt)
    one = [dom.check(Xt[i : i + 1], gt[i : i + 1]) for i in range(40)]
    np.testing.assert_array_equal(np.concatenate([r["in_domain"] for r in one]), batch["in_domain"])
    np.testing.assert_allclose(np.concatenate([r["distance"] for r in one]), batch["distance"], rtol=1e-12)
    assert np.isinf(batch["distance"][[3, 7]]).all() and not batch["in_domain"][[3, 7, 11]].any()
    assert np.isnan(batch["gravity_angle_rad"][11]) and np.isfinite(batch["distance"][11])
    assert 0 < batch["in_domain"].mean() < 1 and len(dom.check(Xt[:0], gt[:0])["in_domain"]) == 0


def test_window_gravity_is_the_unit_mean():
    acc = np.zeros((100, 3))
    acc[:, 2] = 9.8
    acc[50:, 1] = 9.8
    g = window_gravity(acc, [0, 50], 50)
    np.testing.assert_allclose(g, [[0, 0, 1], [0, np.sqrt(0.5), np.sqrt(0.5)]], atol=1e-12)
    assert np.isnan(window_gravity(np.zeros((10, 3)), [0], 10)).all()


def test_model_records_frame_domain_and_positions_data_only(phone_model, gravity_model):
    info = json.loads((phone_model / JSON_NAME).read_text())
    assert info["feature_frame"] == "phone"
    dom = info["domain"]
    assert set(dom["positions"]) <= {"hand-flat", "hand-tilted"} and sum(dom["positions"].values()) == info["training_data"]["n_windows"]
    assert dom["gravity_check"] is True and 0 < dom["gravity_threshold_rad"] < np.pi
    assert dom["distance_threshold"] > 0 and dom["quantile"] == 0.99
    with np.load(phone_model / ARRAYS_NAME, allow_pickle=False) as z:  # plain arrays, no pickle
        names = set(z.files)
        assert {"domain__center", "domain__class_precisions", "domain__gravity_dirs"} <= names
        assert all(z[k].dtype.kind in "biufU" for k in z.files)
    m = load_model(phone_model)
    assert m.frame == "phone" and m.domain is not None and m.domain.distance_threshold == dom["distance_threshold"]
    g = load_model(gravity_model)
    assert g.frame == "gravity" and g.domain.frame == "gravity" and g.domain.gravity_check is False
    card = model_card(info)
    assert "## Domain\n" in card and "hand-" in card and "held-out" in card


# ---------------------------------------------------------------- predict


def test_predict_json_in_domain_and_fraction(phone_model, new_subject, tmp_path, capsys):
    path = tmp_path / "in.csv"
    write_gaitml_csv(new_subject, path)
    code, out, err = _cli(["predict", phone_model, path, "--json", "--out", tmp_path / "p.csv"], capsys)
    assert code == 0
    js = json.loads(out)
    flags = [w["in_domain"] for w in js["windows"]]
    assert all(isinstance(f, bool) for f in flags)
    assert js["out_of_domain_fraction"] == pytest.approx(1 - np.mean(flags))
    assert js["out_of_domain_fraction"] <= 0.10  # a new walker of the training positions is in domain
    assert not _warnings(err)
    import pandas as pd

    table = pd.read_csv(tmp_path / "p.csv")
    assert "in_domain" in table and len(table) == len(flags)


def test_predict_warns_once_on_a_phone_held_upside_down_and_scaled(phone_model, new_subject, tmp_path, capsys):
    q = Rotation.from_euler("x", 180, degrees=True).as_matrix()
    odd = new_subject.replace(acc=1.6 * new_subject.acc @ q.T, gyr=new_subject.gyr @ q.T, check_units=False)
    write_gaitml_csv(odd, tmp_path / "odd.csv")
    code, out, err = _cli(["predict", phone_model, tmp_path / "odd.csv", "--json"], capsys)
    assert code == 0
    js = json.loads(out)
    assert js["out_of_domain_fraction"] > 0.9
    warns = _warnings(err)
    # one domain warning; the only other line a screen-down phone may add is the side-step direction's (unsure there)
    domain = [w for w in warns if "outside the model's training domain" in w]
    assert len(domain) == 1 and "%" in domain[0]
    assert all("direction is unsure" in w for w in warns if w not in domain) and len(warns) <= 2


def test_gravity_frame_model_reads_a_rotated_phone_like_the_original(gravity_model, new_subject):
    m = load_model(gravity_model)
    base = predict_recording(m, new_subject)
    q = Rotation.random(random_state=5).as_matrix()
    rot = predict_recording(m, new_subject.replace(acc=new_subject.acc @ q.T, gyr=new_subject.gyr @ q.T, check_units=False))
    assert (base["mode"] == rot["mode"]).all()  # the frame stored in model.json is the one used
    np.testing.assert_array_equal(base["in_domain"].to_numpy(bool), rot["in_domain"].to_numpy(bool))
    assert out_of_domain_fraction(base["in_domain"]) <= 0.10


def test_foot_mounted_imu_is_out_of_domain(phone_model):
    from gaitml.io import read_recording

    rec = read_recording(shared("gaitmap-example", "imu_sample.csv.gz"))
    table = predict_recording(load_model(phone_model), rec)
    assert out_of_domain_fraction(table["in_domain"]) >= 0.9


# ---------------------------------------------------------------- pdr


def test_pdr_moves_out_of_domain_steps_forward(phone_model, new_subject, tmp_path, capsys):
    from gaitml.models import load_model
    from gaitml.pdr import run_pdr

    m = load_model(phone_model)
    # second half of the recording turned upside down: those steps are out of domain
    q = Rotation.from_euler("y", 180, degrees=True).as_matrix()
    half = new_subject.n_samples // 2
    acc, gyr = new_subject.acc.copy(), new_subject.gyr.copy()
    acc[half:], gyr[half:] = acc[half:] @ q.T, gyr[half:] @ q.T
    rec = new_subject.replace(acc=acc, gyr=gyr, check_units=False)
    res = run_pdr(rec, model=m, heading="gyro", step_length="reference")
    steps = res.steps
    ood = steps["in_domain"].to_numpy(dtype=object) == False  # noqa: E712 - object array of bools
    assert res.info["out_of_domain_steps"] == int(ood.sum()) > 0
    assert (steps.loc[ood, "mode"] == "walk").all()
    # moved along the facing heading: displacement = L (sin theta, cos theta)
    xy = res.trajectory[["x_m", "y_m"]].to_numpy()
    d = np.diff(xy, axis=0)[ood]
    th = steps.loc[ood, "heading_rad"].to_numpy(float)
    L = steps.loc[ood, "step_length_m"].to_numpy(float)
    np.testing.assert_allclose(d, np.column_stack([L * np.sin(th), L * np.cos(th)]), atol=1e-9)
    # the CLI reports them in the JSON and the table
    write_gaitml_csv(rec, tmp_path / "r.csv")
    code, out, err = _cli(["pdr", tmp_path / "r.csv", "--model", phone_model, "--json", "--heading", "gyro"], capsys)
    js = json.loads(out)
    assert code == 0 and js["out_of_domain_steps"] == sum(r.get("in_domain") is False for r in js["trajectory"]) > 0
    assert len(_warnings(err)) <= 1
    code, out, err = _cli(["pdr", tmp_path / "r.csv", "--model", phone_model, "--heading", "gyro"], capsys)
    assert code == 0 and "out of the model's domain:" in out


# ---------------------------------------------------------------- old models


def _strip_domain(src, dst):
    shutil.copytree(src, dst)
    info = json.loads((dst / JSON_NAME).read_text())
    info.pop("domain")
    with np.load(dst / ARRAYS_NAME, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files if not k.startswith("domain__")}
    np.savez_compressed(dst / ARRAYS_NAME, **arrays)
    info["files"][ARRAYS_NAME] = sha256_file(dst / ARRAYS_NAME)
    info["settings_sha256"] = settings_sha256(info)
    (dst / JSON_NAME).write_text(json.dumps(info, indent=2))
    return dst


def test_old_model_without_domain_loads_and_says_so_once(phone_model, new_subject, tmp_path, capsys):
    old = _strip_domain(phone_model, tmp_path / "old")
    m = load_model(old)
    assert m.domain is None and m.frame == "phone"
    write_gaitml_csv(new_subject, tmp_path / "in.csv")
    code, out, err = _cli(["predict", old, tmp_path / "in.csv", "--json"], capsys)
    js = json.loads(out)
    assert code == 0 and js["out_of_domain_fraction"] is None and all(w["in_domain"] is None for w in js["windows"])
    assert _warnings(err) == [f"gaitml: warning: {NO_DOMAIN_WARNING}"]
    code, out, err = _cli(["pdr", tmp_path / "in.csv", "--model", old, "--json"], capsys)
    js = json.loads(out)
    assert code == 0 and js["out_of_domain_steps"] is None
    assert _warnings(err) == [f"gaitml: warning: {NO_DOMAIN_WARNING}"]
    assert "No domain record" in model_card(m.info)


def test_attach_domain_to_an_old_model_keeps_its_classifier(phone_model, tmp_path):
    from gaitml.errors import ConfigError
    from gaitml.pipeline.runner import attach_training_domain

    old = _strip_domain(phone_model, tmp_path / "old")
    cfg = parse_config(json.loads(json.dumps(SMALL)))
    new = attach_training_domain(cfg, old, tmp_path / "new")
    ref = load_model(phone_model)
    assert new.domain.distance_threshold == pytest.approx(ref.domain.distance_threshold)
    assert "not refitted" in load_model(tmp_path / "new").info["domain"]["summary"]["recorded"]
    np.testing.assert_array_equal(load_model(tmp_path / "new").estimator.coef_, ref.estimator.coef_)
    with pytest.raises(ConfigError, match="not the one model"):
        attach_training_domain(cfg.with_values({"windows.length_s": 2.0}), old, tmp_path / "bad")


def test_a_class_with_two_windows_gets_a_positive_definite_precision():
    """Ledoit-Wolf leaves the covariance of a two-window class singular (its shrinkage is
    estimated as 0); the record must still be usable (a step-window model with few windows of one
    mode hit this)."""
    from gaitml.models.domain import _class_gaussians

    rng = np.random.default_rng(0)
    Z = rng.standard_normal((42, 52))
    y = np.array(["walk"] * 40 + ["backward"] * 2)
    means, precs = _class_gaussians(Z, y, ["backward", "walk"])
    for P in precs:
        np.linalg.cholesky(P)  # raises if not positive definite
        assert np.all(np.isfinite(P))
    assert np.allclose(means[0], Z[40:].mean(axis=0))
    # usable distances: new windows of the same distribution are about as far from the two-window
    # class as from a one-window class (unit covariance: sqrt(p) ~ 7 plus the offset), not hundreds
    fresh = rng.standard_normal((200, 52))
    d_two = np.sqrt(np.einsum("ij,jk,ik->i", fresh - means[0], precs[0], fresh - means[0]))
    d_unit = np.linalg.norm(fresh - means[0], axis=1)
    assert np.median(d_two) <= np.median(d_unit) + 1e-9
    assert np.median(d_two) > 0.5 * np.median(d_unit)
    names = [f"f{i}" for i in range(52)]
    grav = np.tile([[0.0, 0.0, 1.0]], (42, 1))
    record = fit_domain(Z, y, np.repeat(np.arange(21), 2), grav, feature_names=names, feature_set="all52", frame="phone")
    assert np.isfinite(record.distances(Z)).all()
