"""The orientation-dynamics part of the domain record: descriptors, distances, running medians, persistence, the CLI.

The descriptors, distances and running medians are checked against straightforward
per-window loops; a small leave-one-position-out run on the simulator must flag the
left-out position and keep new subjects of the trained positions.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.stats import skew
from sklearn.covariance import LedoitWolf

from gaitml.models.domain import (
    DYNAMICS_EVERY,
    DYNAMICS_NAMES,
    DYNAMICS_SPAN,
    DomainModel,
    fit_domain,
    orientation_dynamics,
    running_median,
)

ROOT = Path(__file__).resolve().parents[2]


def _reference_dynamics(a: np.ndarray, w: np.ndarray, chunk: int) -> np.ndarray:
    """One window, written out plainly."""
    g = a.mean(axis=0) / np.linalg.norm(a.mean(axis=0))
    angles = []
    for c in range(max(1, len(a) // chunk)):
        m = a[c * chunk : (c + 1) * chunk].mean(axis=0)
        angles.append(np.degrees(np.arccos(np.clip(m @ g / np.linalg.norm(m), -1, 1))))
    v = a @ g
    h = a - np.outer(v, g)
    ch = np.cov(h.T, bias=True)
    ev, evec = np.linalg.eigh(ch)
    h1 = h @ evec[:, 2]
    cw = np.cov(w.T, bias=True)
    mag = np.linalg.norm(w, axis=1)
    return np.array(
        [
            np.mean(angles),
            np.log(v.var() / np.trace(ch)),
            abs(np.corrcoef(v, h1)[0, 1]),
            ev[1] / ev[2],
            np.log(v.std()),
            0.5 * np.log(np.trace(ch)),
            np.max(angles),
            skew(v),
            np.log(mag.mean()),
            np.log(mag.std()),
            g @ cw @ g / np.trace(cw),
            np.linalg.eigvalsh(cw)[2] / np.trace(cw),
            evec[:, 2] @ cw @ evec[:, 2] / np.trace(cw),
        ]
    )


def _walk(seed: int, n: int = 600):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 50.0
    acc = np.column_stack(
        [1.5 * np.sin(2 * np.pi * 1.8 * t), 0.8 * np.cos(2 * np.pi * 0.9 * t + 0.3), 9.81 + 2.0 * np.sin(2 * np.pi * 1.8 * t)]
    )
    gyr = np.column_stack([0.6 * np.sin(2 * np.pi * 0.9 * t), 0.2 * np.cos(2 * np.pi * 1.8 * t), 0.1 * np.sin(2 * np.pi * 0.9 * t + 1)])
    return acc + 0.3 * rng.standard_normal(acc.shape), gyr + 0.05 * rng.standard_normal(gyr.shape)


def test_orientation_dynamics_matches_a_per_window_loop():
    acc, gyr = _walk(1)
    starts = np.array([0, 37, 75, 300, 500])
    ends = np.array([75, 112, 150, 340, 575])  # two lengths, as step windows have
    got = orientation_dynamics(acc, gyr, starts, ends, 50.0)
    assert got.shape == (5, len(DYNAMICS_NAMES))
    for i, (s, e) in enumerate(zip(starts, ends, strict=True)):
        keep = np.arange(s, e)
        keep = keep[keep % 2 == 0]  # at 50 Hz the descriptors use every second sample (25 Hz; chunks of 0.3 s: 8 samples)
        np.testing.assert_allclose(got[i], _reference_dynamics(acc[keep], gyr[keep], 8), rtol=1e-9, atol=1e-9)


def test_orientation_dynamics_ignore_how_the_phone_is_held():
    acc, gyr = _walk(2)
    starts = np.arange(0, 500, 37)
    base = orientation_dynamics(acc, gyr, starts, starts + 75, 50.0)
    for seed in range(3):
        m = Rotation.random(random_state=seed).as_matrix()
        np.testing.assert_allclose(orientation_dynamics(acc @ m.T, gyr @ m.T, starts, starts + 75, 50.0), base, rtol=1e-7, atol=1e-7)


def test_running_median_matches_a_loop_and_never_crosses_recordings():
    rng = np.random.default_rng(3)
    d = rng.random(50)
    d[7] = np.nan
    seq = np.repeat(["a", "b"], [30, 20])
    got = running_median(d, 5, seq)
    for i in range(50):
        first = 0 if i < 30 else 30
        np.testing.assert_allclose(got[i], np.nanmedian(d[max(first, i - 4) : i + 1]))


def _fit(seed: int = 0):
    rng = np.random.default_rng(seed)
    q = len(DYNAMICS_NAMES)
    n = 600
    y = np.repeat(["walk", "run"], n // 2)
    pos = np.tile(np.repeat(["belt", "bag"], n // 4), 2)
    shift = (y == "run")[:, None] * 3.0 + (pos == "bag")[:, None] * np.linspace(-2, 2, q)
    Q = rng.standard_normal((n, q)) @ rng.standard_normal((q, q)) * 0.3 + shift
    X = rng.standard_normal((n, 4)) + (y == "run")[:, None]
    groups = np.tile(np.repeat([f"s{i}" for i in range(6)], 25), 4)
    seq = np.repeat(np.arange(n // 50), 50)
    dom = fit_domain(
        X,
        y,
        groups,
        np.tile([0.0, 0.0, 1.0], (n, 1)),
        feature_names=list("abcd"),
        feature_set="test",
        frame="gravity",
        positions=pos,
        dynamics=Q,
        sequence=seq,
    )
    return dom, Q, y, pos


def test_dynamics_distance_is_the_smallest_mahalanobis_distance_to_the_mode_position_gaussians():
    dom, Q, y, pos = _fit()
    assert dom.dynamics["labels"] == ["run|bag", "run|belt", "walk|bag", "walk|belt"]
    c, s = Q.mean(axis=0), Q.std(axis=0)
    Z = (Q - c) / s
    lab = np.char.add(np.char.add(y, "|"), pos)
    ref = np.full(len(Q), np.inf)
    for label in sorted(set(lab)):
        lw = LedoitWolf().fit(Z[lab == label])
        prec = np.linalg.inv(lw.covariance_)
        for i in range(len(Q)):
            dz = Z[i] - lw.location_
            ref[i] = min(ref[i], np.sqrt(dz @ prec @ dz))
    probe = np.vstack([Q[:40], Q[:3] + 5.0])
    ref = np.concatenate([ref[:40], [np.inf] * 3])
    for i in range(3):
        dz_all = []
        for label in sorted(set(lab)):
            lw = LedoitWolf().fit(Z[lab == label])
            dz = (probe[40 + i] - c) / s - lw.location_
            dz_all.append(np.sqrt(dz @ np.linalg.inv(lw.covariance_) @ dz))
        ref[40 + i] = min(dz_all)
    np.testing.assert_allclose(dom.dynamics_distances(probe), ref, rtol=1e-6)
    bad = probe.copy()
    bad[5, 2] = np.nan
    assert np.isinf(dom.dynamics_distances(bad)[5])


def test_check_uses_the_span_median_of_the_computed_windows_and_flags_a_stretch_unlike_training():
    dom, Q, _, _ = _fit()
    assert dom.dynamics["every"] == DYNAMICS_EVERY == dom.dynamics_every > 1
    X = np.zeros((60, 4))
    grav = np.tile([0.0, 0.0, 1.0], (60, 1))
    stretch = np.vstack([Q[:30], Q[:30] + 8.0])  # 30 trained-like windows, then 30 of another position
    res = dom.check(X, grav, stretch)
    # plainly: window i decides on the median of the distances of windows 0, every, 2 every, ... among its last 20
    d = dom.dynamics_distances(stretch)
    ref = [np.median([d[j] for j in range(max(0, i - DYNAMICS_SPAN + 1), i + 1) if j % DYNAMICS_EVERY == 0]) for i in range(60)]
    np.testing.assert_array_equal(res["dynamics_distance"], ref)
    # the computed windows only (what predict computes) give the same, bit for bit
    rows = dom.dynamics_rows(60)
    np.testing.assert_array_equal(rows, np.arange(0, 60, DYNAMICS_EVERY))
    for k in ("dynamics_distance", "in_domain", "distance"):
        np.testing.assert_array_equal(dom.check(X, grav, stretch[rows])[k], res[k])
    assert res["in_domain"][:30].mean() > 0.9
    assert not res["in_domain"][30 + DYNAMICS_SPAN // 2 :].any()
    # without the dynamics the check is today's (one-window callers)
    assert np.isnan(dom.check(X, grav)["dynamics_distance"]).all()


def test_the_record_round_trips_and_an_old_record_checks_as_before():
    dom, Q, _, _ = _fit()
    info, arrays = dom.to_json(), dom.to_arrays()
    assert "domain__dyn_precisions" in arrays and "domain__dyn_precisions" in info["arrays"]
    back = DomainModel.from_json(info, arrays)
    X = np.zeros((40, 4))
    grav = np.tile([0.0, 0.0, 1.0], (40, 1))
    for k in ("in_domain", "dynamics_distance", "distance"):
        np.testing.assert_array_equal(back.check(X, grav, Q[:40] + 3)[k], dom.check(X, grav, Q[:40] + 3)[k])
    old_info = {k: v for k, v in info.items() if k != "dynamics"}
    old_arrays = {k: v for k, v in arrays.items() if not k.startswith("domain__dyn_")}
    old = DomainModel.from_json(old_info, old_arrays)
    assert old.dynamics is None and "dynamics" not in old.to_json()
    res = old.check(X, grav, Q[:40] + 100.0)  # dynamics given but not recorded: ignored
    np.testing.assert_array_equal(res["in_domain"], dom.check(X, grav)["in_domain"])
    broken = {**arrays, "domain__dyn_means": arrays["domain__dyn_means"][:, :5]}
    from gaitml.errors import ModelError

    with pytest.raises(ModelError, match="dyn_means"):
        DomainModel.from_json(info, broken)


def test_a_trained_gyroscope_model_records_the_dynamics_and_predict_uses_them(tmp_path):
    from gaitml.cli import main
    from gaitml.models import load_model, predict_recording
    from gaitml.simulate import sample_subjects, simulate_recording
    from gaitml.simulate.positions import Placement

    text = (ROOT / "experiments" / "positions.toml").read_text()
    text = text.replace("subjects = 12", "subjects = 3").replace("duration_s = 150.0", "duration_s = 20.0")
    text = text.replace("cross_validate = true", "cross_validate = false")
    text = text.replace('"hand-flat", "hand-tilted", "front-pocket", "back-pocket", "belt", "swinging-hand", "bag"', '"hand-flat", "belt"')
    (tmp_path / "cfg.toml").write_text(text)
    assert main(["train", str(tmp_path / "cfg.toml"), "--out", str(tmp_path / "model")]) == 0
    model = load_model(tmp_path / "model")
    assert model.domain.dynamics is not None and model.domain.dynamics["span"] == DYNAMICS_SPAN
    assert set(model.domain.dynamics["labels"]) <= {
        f"{m}|{p}" for m in ("walk", "backward", "run", "side_left", "side_right") for p in ("hand-flat", "belt")
    }
    card = (tmp_path / "model" / "MODEL.md").read_text()
    assert "Orientation dynamics" in card and f"one window in {DYNAMICS_EVERY}: windows 0, {DYNAMICS_EVERY}," in card
    subject = sample_subjects(1, 41)[0]
    rec = simulate_recording(
        subject, duration_s=40.0, modes=["walk"], seed=41, placement=Placement.random("swinging-hand", np.random.default_rng(41))
    )
    t = predict_recording(model, rec)
    dom = model.domain
    starts = t["start"].to_numpy(np.int64)
    q = orientation_dynamics(rec.acc, rec.gyr, starts, starts + 75, rec.sampling_rate_hz)
    from gaitml.models.domain import window_gravity

    ref = dom.check(_features(rec, starts), window_gravity(rec.acc, starts, 75), q)
    np.testing.assert_array_equal(t["in_domain"].astype(bool).to_numpy(), ref["in_domain"])
    assert np.isfinite(ref["dynamics_distance"]).all()
    # the table says why a window is flagged: the running median the decision used
    np.testing.assert_allclose(t["dynamics_distance"].to_numpy(float), ref["dynamics_distance"])
    # a recording of one window: its dynamics are checked too (the one-window short path is for callers without them)
    one = rec.slice(int(starts[20]), int(starts[20]) + 75)
    t1 = predict_recording(model, one)
    q1 = orientation_dynamics(one.acc, one.gyr, [0], [75], one.sampling_rate_hz)
    ref1 = dom.check(_features(one, np.array([0])), window_gravity(one.acc, [0], 75), q1)
    assert bool(t1["in_domain"].iloc[0]) == bool(ref1["in_domain"][0])
    assert ref1["dynamics_distance"][0] == dom.dynamics_distances(q1)[0]
    # a long file read chunk by chunk gives the flags of the whole-file run (context for the running median,
    # chunk offsets on the descriptors' sample grid)
    from gaitml.chunked_run import long_predict
    from gaitml.io.gaitml_csv import write_gaitml_csv

    write_gaitml_csv(rec, tmp_path / "rec.csv")
    chunked = long_predict(model, tmp_path / "rec.csv", chunk_s=7.0, progress=False)
    np.testing.assert_array_equal(chunked["in_domain"].astype(bool).to_numpy(), t["in_domain"].astype(bool).to_numpy())
    np.testing.assert_allclose(chunked["dynamics_distance"].to_numpy(float), t["dynamics_distance"].to_numpy(float))
    # the descriptors of every dom.dynamics_every-th window only: chunk offsets must lie on that window grid too.
    # At 50 Hz the hop (37) and the sample step (2) already align chunks to every second window, so a record
    # computing every fourth window (4 divides the span) is what tells an aligned grid from a shifted one
    import dataclasses

    import gaitml.chunked_run as longrun

    m4 = dataclasses.replace(model, domain=dataclasses.replace(dom, dynamics={**dom.dynamics, "every": 4}))
    whole4 = predict_recording(m4, rec)
    offsets = []
    real = longrun._window_chunks

    def spy(*args, **kwargs):
        for ch, length, hop in real(*args, **kwargs):
            offsets.append((ch.offset, hop))
            yield ch, length, hop

    longrun._window_chunks = spy
    try:
        for chunk_s in (4.3, 7.0):
            # the step rules and the still_unsure mark off: their chunks start on adaptive's 1 s cadence grid too, which
            # at every = 4 makes 76 s chunks (one chunk of this 40 s file); this checks the dynamics' own grid
            chunked = long_predict(
                m4, tmp_path / "rec.csv", chunk_s=chunk_s, progress=False, run_min_cadence_hz=0, still_step_veto=0, mark_still_unsure=False
            )
            np.testing.assert_array_equal(chunked["in_domain"].astype(bool).to_numpy(), whole4["in_domain"].astype(bool).to_numpy())
            np.testing.assert_allclose(chunked["dynamics_distance"].to_numpy(float), whole4["dynamics_distance"].to_numpy(float))
    finally:
        longrun._window_chunks = real
    assert len(offsets) > 4 and all(off % (4 * hop) == 0 and off % 2 == 0 for off, hop in offsets)


def test_no_windows_and_one_window_with_dynamics():
    dom, Q, _, _ = _fit()
    res = dom.check(np.zeros((0, 4)), np.zeros((0, 3)), np.zeros((0, len(DYNAMICS_NAMES))))
    assert all(len(v) == 0 for v in res.values())
    far = Q[:1] + 8.0
    one = dom.check(np.zeros((1, 4)), np.array([[0.0, 0.0, 1.0]]), far)
    assert one["dynamics_distance"][0] == dom.dynamics_distances(far)[0] > dom.dynamics["threshold"]
    assert not one["in_domain"][0]
    assert np.isnan(dom.check(np.zeros((1, 4)), np.array([[0.0, 0.0, 1.0]]))["dynamics_distance"][0])


def _features(rec, starts):
    from gaitml.features import features_from_arrays

    return features_from_arrays(rec.acc, rec.gyr, rec.sampling_rate_hz, starts, 75, "all52+gyro", "phone")


def test_train_domain_dynamics_false_records_features_and_gravity_only(tmp_path):
    """``train.domain_dynamics = false``: an all52+gyro model without the orientation-dynamics part
    (the shipped models/demo, trained on several carrying positions, has it)."""
    from gaitml.models import load_model
    from gaitml.pipeline.config import parse_config
    from gaitml.pipeline.runner import train_config

    cfg = parse_config(
        {
            "name": "no-dyn",
            "data": {"simulated": {"subjects": 3, "duration_s": 30.0}},
            "features": {"set": "all52+gyro"},
            "train": {"cross_validate": False, "domain_dynamics": False},
        }
    )
    train_config(cfg, out_dir=tmp_path / "m", progress=False)
    model = load_model(tmp_path / "m")
    assert model.domain is not None and model.domain.dynamics is None
    assert load_model(ROOT / "models" / "demo").domain.dynamics is not None
    with pytest.raises(Exception, match="domain_dynamics"):
        parse_config({"name": "x", "train": {"domain_dynamics": "no"}})
