"""Pocket flips: the phone put into a pocket another way round (180 deg turns about its own axes, gaitml.pipeline.augment)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import ConfigError, InputError
from gaitml.pipeline.augment import FLIP_AXES, augment_recordings, augmented_set, flip_rotation, without_copies
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import prepare_data
from gaitml.recording import Recording
from tests.pipeline.test_augment import _config, _csv_config, _csv_folder, _swinging, _tyrex_swinging, assert_same_domain

FS = 50.0


def _pocket(n_s=30.0, position="front-pocket", subject="Ann", gyr=True):
    """A phone top up in a pocket, screen forward: gravity mostly along +y, the thigh swinging about the phone's x."""
    t = np.arange(0, n_s, 1 / FS)
    acc = np.column_stack(
        [1.0 + 2.0 * np.sin(2 * np.pi * 0.9 * t), 9.5 + 3.0 * np.sin(2 * np.pi * 1.8 * t), 1.5 + np.cos(2 * np.pi * 0.9 * t)]
    )
    w = np.column_stack([2.5 * np.sin(2 * np.pi * 0.9 * t + 0.3), 0.4 * np.sin(2 * np.pi * 1.8 * t), 0.6 * np.cos(2 * np.pi * 0.9 * t)])
    labels = np.full(len(t), "walk", dtype=object)
    return Recording(
        acc=acc,
        gyr=w if gyr else None,
        sampling_rate_hz=FS,
        labels=labels,
        meta={"position": position, "subject": subject, "id": f"{subject}-{position}"},
    )


def test_a_flip_is_a_proper_half_turn_about_its_axis():
    for k, axis in enumerate(FLIP_AXES):
        F = flip_rotation(axis)
        e = np.eye(3)[k]
        assert np.allclose(F @ F.T, np.eye(3)) and np.isclose(np.linalg.det(F), 1.0)  # a rotation, not a mirror
        assert np.allclose(F @ F, np.eye(3)) and np.isclose(np.trace(F), -1.0)  # by 180 deg
        assert np.allclose(F @ e, e)  # about its own axis
    # the three compose like the turns of a rigid body: two flips make the third
    assert np.allclose(flip_rotation("x") @ flip_rotation("y"), flip_rotation("z"))
    with pytest.raises(InputError, match="x, y or z"):
        flip_rotation("w")


def test_flipped_copies_turn_acc_and_gyro_alike_and_reach_the_other_pocket_ways():
    rec = _pocket()
    out = augment_recordings([rec], 0, flips=["x", "y", "z"], flip_positions=["front-pocket"])
    assert [c.meta["augmented"] for c in out] == ["flipped about x", "flipped about y", "flipped about z"]
    for axis, c in zip(FLIP_AXES, out, strict=True):
        F = flip_rotation(axis)
        np.testing.assert_allclose(c.acc, rec.acc @ F.T)
        np.testing.assert_allclose(c.gyr, rec.gyr @ F.T)
        # a proper rotation keeps the handedness of the pair: acc x gyr turns with them (a mirror would flip its sign)
        np.testing.assert_allclose(np.cross(c.acc, c.gyr), np.cross(rec.acc, rec.gyr) @ F.T, atol=1e-9)
        np.testing.assert_allclose(np.einsum("ij,ij->i", c.acc, c.gyr), np.einsum("ij,ij->i", rec.acc, rec.gyr), atol=1e-9)
        assert c.reference == {} and np.array_equal(c.labels, rec.labels)
    g0 = rec.acc.mean(0)
    gx, gy, gz = (c.acc.mean(0) for c in out)
    assert gy[1] > 9 and gx[1] < -9 and gz[1] < -9  # top up kept by the turn about y; top down about x and z
    assert np.sign(gy[2]) == -np.sign(g0[2]) and np.sign(gz[2]) == np.sign(g0[2])  # the screen reversed about y, kept about z


def test_flips_only_in_their_positions_and_without_a_gyroscope_too():
    recs = [_pocket(), _pocket(position="back-pocket", gyr=False), _pocket(position="hand"), _swinging([0.0, 0.0, 1.0])]
    out = augment_recordings(recs, 0, flips=["y"])  # default positions: the pockets
    assert [c.meta["position"] for c in out] == ["front-pocket", "back-pocket"]
    assert out[1].gyr is None and np.allclose(out[1].acc, recs[1].acc @ flip_rotation("y").T)
    assert augment_recordings(recs, 0) == []
    with pytest.raises(InputError, match="twice"):
        augment_recordings(recs, 0, flips=["y", "y"])
    with pytest.raises(InputError, match="got 'q'"):
        augment_recordings(recs, 0, flips=["q"])


def test_flips_with_swing_turns_flip_every_grip_and_leave_the_turns_as_they_were():
    swing = _swinging([0.0, 0.0, 1.0], n_s=30.0)
    swing = swing.replace(labels=np.full(swing.n_samples, "walk", dtype=object))
    recs = [swing, _pocket()]
    turns_only = augment_recordings(recs, 3, ["swinging-hand"], seed=4)
    both = augment_recordings(recs, 3, ["swinging-hand"], seed=4, flips=["x", "z"], flip_positions=["swinging-hand", "front-pocket"])
    # the swinging hand: 4 grips x (1 + 2 flips) - the original = 11 copies; the pocket: 2
    assert len(both) == 11 + 2 and sum(c.meta["position"] == "front-pocket" for c in both) == 2
    # flips do not move the swing turns' draws: the turned copies are the same
    for a, b in zip(turns_only, both[:3], strict=True):
        assert a.meta["augmented"] == b.meta["augmented"] and np.array_equal(a.acc, b.acc)
    # the flipped turned grips are the turned grips flipped
    turned = {c.meta["augmented"]: c for c in turns_only}
    for c in both:
        note = c.meta["augmented"]
        if note.startswith("flipped about x, "):
            np.testing.assert_allclose(c.acc, turned[note.removeprefix("flipped about x, ")].acc @ flip_rotation("x").T)


def test_shared_time_gives_every_stretch_to_exactly_one_of_the_flipped_grips():
    recs = [_pocket(n_s=90.0), _pocket(n_s=90.0, position="hand")]
    out, extra = augmented_set(recs, 0, seed=2, share_time=True, flips=["x", "y", "z"])
    assert len(extra) == 3 and out[1] is recs[1]
    walk = np.array([g.labels.astype(str) == "walk" for g in [out[0], *extra]])
    assert np.all(walk.sum(axis=0) == 1) and all(0.15 < w.mean() < 0.35 for w in walk)
    back, _ = without_copies(out, list(range(len(out))))
    assert len(back) == 2 and np.array_equal(back[0].labels, recs[0].labels)


def test_flips_never_enter_the_domain_record(tmp_path):
    """The flipped copies train the classifier only: the domain record equals the one without copies."""
    from gaitml.models import make_model
    from gaitml.pipeline.runner import build_dataset, fit_training_domain

    root = _tyrex_swinging(tmp_path)
    res = []
    for aug in (
        {},
        {"flips": ["x", "y", "z"], "flip_positions": ["swinging-hand"]},
        {"swing_turns": 1, "flips": ["y"], "flip_positions": ["swinging-hand"], "share_time": True},
    ):
        cfg = _config(root, **aug)
        data = prepare_data(cfg, use_cache=False)
        ds = build_dataset(cfg, data, use_cache=False)
        model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed).fit(ds.inputs("features"), ds.y)
        res.append((len(ds), data, fit_training_domain(cfg, data, ds, model)))
    (n0, _, d0), (n1, data1, d1), (n2, data2, d2) = res
    assert n1 == 4 * n0 and abs(n2 - n0) <= 0.1 * n0  # whole copies / one grip per stretch
    assert any("flipped 180 deg about the phone's x/y/z axis" in n for n in data1.notes)
    assert any("flipped about y, turned" in r.meta.get("augmented", "") for r in data2.recordings)
    for d in (d1, d2):
        assert_same_domain(d, d0)


def test_flip_settings_are_validated(tmp_path):
    root = _csv_folder(tmp_path)
    with pytest.raises(ConfigError, match="data.augment.flips has 'w', which is not allowed"):
        _csv_config(root, flips=["w"])
    with pytest.raises(ConfigError, match="data.augment.flips .* lists an item twice"):
        _csv_config(root, flips=["y", "y"])
    with pytest.raises(ConfigError, match="flip_positions is set but data.augment.flips is empty"):
        _csv_config(root, flip_positions=["front-pocket"])
    with pytest.raises(ConfigError, match="data.augment.flips applies to data.source = 'folder'"):
        parse_config({"name": "x", "data": {"source": "simulated", "augment": {"flips": ["y"]}}})
    with pytest.raises(
        ConfigError,
        match=r"flip_positions has \['pocket'\], which matches no recording; positions present: \['front-pocket', 'swinging-hand'\]",
    ):
        prepare_data(_csv_config(root, flips=["y"], flip_positions=["front-pocket", "pocket"]), use_cache=False)
    # the default list names every pocket of the tyrex layout: one present is enough, none is refused
    assert sum(bool(r.meta.get("augmented")) for r in prepare_data(_csv_config(root, flips=["y"]), use_cache=False).recordings) == 2
    with pytest.raises(ConfigError, match=r"flip_positions has \['front-pocket', 'back-pocket', 'pocket'\]"):
        prepare_data(_config(_tyrex_swinging(tmp_path / "swing"), flips=["y"]), use_cache=False)
    # flips alone may share the time (no swing turn needed); unset keys stay out of the resolved config
    cfg = _csv_config(root, flips=["y"], flip_positions=["front-pocket"], share_time=True)
    data = prepare_data(cfg, use_cache=False)
    assert sum(bool(r.meta.get("augmented")) for r in data.recordings) == 2
    assert "flips" not in _csv_config(root, swing_turns=1).resolved()["data"]["augment"]
