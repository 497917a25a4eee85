"""Rotated copies of real recordings: the phone turned in the hand about its swing axis (gaitml.pipeline.augment)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import ConfigError, InputError
from gaitml.pipeline.augment import augment_recordings, axis_rotation, rotate_recording, swing_axis
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import prepare_data
from gaitml.recording import Recording
from tests.io_apps.test_tyrex import android_folder, qualisys_csv

FS = 50.0


def _swinging(axis, n_s=20.0, position="swinging-hand", subject="Ann", turn_axis=(0.0, 0.0, 1.0)):
    """A phone swinging at 0.9 Hz about ``axis`` (phone frame) while the walker turns slowly (0.05 Hz) about ``turn_axis``."""
    t = np.arange(0, n_s, 1 / FS)
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    b = np.asarray(turn_axis, float) / np.linalg.norm(turn_axis)
    gyr = np.outer(2.0 * np.sin(2 * np.pi * 0.9 * t), a) + np.outer(0.4 * np.sin(2 * np.pi * 0.05 * t), b)
    acc = np.tile([0.0, 9.81, 0.0], (len(t), 1)) + np.outer(1.5 * np.sin(2 * np.pi * 1.8 * t), [1.0, 0.3, -0.2])
    return Recording(acc=acc, gyr=gyr, sampling_rate_hz=FS, meta={"position": position, "subject": subject, "id": "r"})


def test_axis_rotation_is_a_rotation_about_its_axis():
    rng = np.random.default_rng(0)
    for _ in range(5):
        k = rng.normal(size=3)
        k /= np.linalg.norm(k)
        th = rng.uniform(-np.pi, np.pi)
        R = axis_rotation(k, th)
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12) and np.isclose(np.linalg.det(R), 1.0)
        assert np.allclose(R @ k, k, atol=1e-12)
        v = np.cross(k, rng.normal(size=3))  # perpendicular to the axis: turned by exactly th
        cosang = (R @ v) @ v / (v @ v)
        assert np.isclose(cosang, np.cos(th), atol=1e-9)


def test_swing_axis_finds_the_swing_not_the_walkers_turns():
    axis = np.array([0.3, -0.4, 0.87])
    est = swing_axis(_swinging(axis).gyr, FS)
    assert abs(est @ (axis / np.linalg.norm(axis))) > 0.99
    with pytest.raises(InputError, match=r"\(n, 3\)"):
        swing_axis(np.zeros((10, 2)), FS)


def test_rotated_copy_keeps_what_a_grip_cannot_change():
    rec = _swinging([0.0, 0.0, 1.0])
    R = axis_rotation([0.0, 0.0, 1.0], 2.0)
    out = rotate_recording(rec, R, "test")
    assert np.allclose(np.linalg.norm(out.acc, axis=1), np.linalg.norm(rec.acc, axis=1))
    assert np.allclose(np.linalg.norm(out.gyr, axis=1), np.linalg.norm(rec.gyr, axis=1))
    assert np.allclose(out.gyr[:, 2], rec.gyr[:, 2]) and np.allclose(out.acc[:, 2], rec.acc[:, 2])  # along the axis
    assert not np.allclose(out.acc[:, :2], rec.acc[:, :2])
    assert out.meta["augmented"] == "test" and rec.meta.get("augmented") is None


def test_copies_only_in_the_named_positions_and_spread_over_the_turn():
    axis = np.array([0.0, 0.0, 1.0])
    recs = [_swinging(axis), _swinging(axis, position="front-pocket"), _swinging(axis, position="hand")]
    assert augment_recordings(recs, 0) == []
    with pytest.raises(InputError, match=">= 0"):
        augment_recordings(recs, -1)
    out = augment_recordings(recs, 3, ["swinging-hand"], seed=5)
    assert len(out) == 3 and all(r.meta["position"] == "swinging-hand" for r in out)
    # the mean gravity direction turned about the swing axis: with the original, 4 grips about 90 deg apart
    g0 = recs[0].acc.mean(0)
    angs = sorted([0.0] + [np.degrees(np.arctan2(*(r.acc.mean(0)[[0, 1]])[::-1]) - np.arctan2(g0[1], g0[0])) % 360 for r in out])
    gaps = np.diff([*angs, angs[0] + 360])
    assert np.all(gaps > 45) and np.all(gaps < 135), gaps
    assert len(augment_recordings(recs, 2, ["swinging-hand", "hand"], seed=5)) == 4
    assert augment_recordings([recs[0].replace(gyr=None)], 2, ["swinging-hand"]) == []


def _tyrex_swinging(root):
    t = np.arange(0, 28, 1 / 60)
    pos = np.column_stack([1000 * np.clip(t - 10, 0, None), np.zeros_like(t), np.full_like(t, 1200.0)])
    for name in ("Alice_Nexus5_NoDist_Swinging", "Bob_Nexus5_NoDist_Swinging"):
        android_folder(root, name, dt_s=-1.5)
        qualisys_csv(root, name, t, pos, np.tile(np.eye(3), (len(t), 1, 1)))
    return root


def _config(root, **augment):
    raw = {
        "name": "aug",
        "seed": 3,
        "data": {
            "source": "folder",
            "path": str(root),
            "label": "mode",
            "labels": ["walk", "still"],
            "labelling": {"moving_speed_ms": 0.3},
            **({"augment": augment} if augment else {}),
        },
        "features": {"set": "all52+gyro"},
    }
    return parse_config(raw, base_dir=root)


def test_folder_config_adds_the_copies_in_the_same_group(tmp_path):
    root = _tyrex_swinging(tmp_path)
    plain = prepare_data(_config(root), use_cache=False)
    assert len(plain.recordings) == 2 and "augment" not in _config(root).resolved()["data"]
    data = prepare_data(_config(root, swing_turns=2), use_cache=False)
    assert len(data.recordings) == 6 and sorted(data.groups) == ["Alice"] * 3 + ["Bob"] * 3
    for orig in data.recordings[:2]:
        copies = [r for r in data.recordings[2:] if r.meta["subject"] == orig.meta["subject"]]
        assert len(copies) == 2
        for c in copies:
            assert c.meta["augmented"] and np.array_equal(c.labels, orig.labels)
            assert np.allclose(np.linalg.norm(c.acc, axis=1), np.linalg.norm(orig.acc, axis=1))
    assert any("augmented: 4 copies" in n for n in data.notes)
    with pytest.raises(ConfigError, match="matches no recording"):
        prepare_data(_config(root, swing_turns=2, positions=["back-pocket"]), use_cache=False)
    with pytest.raises(ConfigError, match="data.augment.swing_turns applies to data.source = 'folder'"):
        parse_config({"name": "x", "data": {"source": "simulated", "augment": {"swing_turns": 1}}})


def test_shared_time_gives_every_stretch_to_exactly_one_grip():
    from gaitml.pipeline.augment import augmented_set

    rec = _swinging([0.0, 0.0, 1.0], n_s=60.0)
    rec = rec.replace(labels=np.full(rec.n_samples, "walk", dtype=object))
    other = _swinging([0.0, 0.0, 1.0], n_s=60.0, position="front-pocket")
    other = other.replace(labels=np.full(other.n_samples, "walk", dtype=object))
    out, extra = augmented_set([rec, other], 3, ["swinging-hand"], seed=2, share_time=True)
    assert len(out) == 2 + 3 and len(extra) == 3 and out[1] is other
    grips = [out[0], *extra]
    walk = np.array([g.labels.astype(str) == "walk" for g in grips])
    assert np.all(walk.sum(axis=0) == 1)  # each sample trained once, in one grip
    assert all(0.15 < w.mean() < 0.35 for w in walk)  # about a quarter each
    assert all(c.meta["augmented_shares_time"] for c in extra) and "augmented" not in out[0].meta
    plain, extra2 = augmented_set([rec, other], 3, ["swinging-hand"], seed=2)
    assert len(plain) == 5 and plain[0] is rec and all(np.all(c.labels.astype(str) == "walk") for c in extra2)


def test_the_domain_record_is_fitted_on_the_recordings_as_they_were(tmp_path):
    """Copies train the classifier only: the domain of an augmented training set equals the one without copies."""
    from gaitml.models import make_model
    from gaitml.pipeline.runner import build_dataset, fit_training_domain

    root = _tyrex_swinging(tmp_path)
    domains = []
    for aug in ({}, {"swing_turns": 3, "share_time": True}, {"swing_turns": 2}):
        cfg = _config(root, **aug)
        data = prepare_data(cfg, use_cache=False)
        ds = build_dataset(cfg, data, use_cache=False)
        model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed).fit(ds.inputs("features"), ds.y)
        domains.append((len(ds), fit_training_domain(cfg, data, ds, model)))
    (n0, d0), (n1, d1), (n2, d2) = domains
    assert n2 == 3 * n0 and abs(n1 - n0) <= 0.1 * n0  # copies of the whole recording / one grip per stretch
    for d in (d1, d2):
        assert np.isclose(d.distance_threshold, d0.distance_threshold, rtol=1e-9)
        assert_same_domain(d, d0)


def assert_same_domain(d, d0):
    """Two domain records are the same record: positions, classes, gravity threshold and every array."""
    assert d.positions == d0.positions and d.classes == d0.classes
    assert np.isclose(d.gravity_threshold_rad, d0.gravity_threshold_rad, rtol=1e-9)
    a, b = d.to_arrays(), d0.to_arrays()
    assert sorted(a) == sorted(b)
    for k in a:
        np.testing.assert_allclose(a[k], b[k], rtol=1e-9, atol=1e-12, err_msg=k)


def _csv_folder(root):
    """A folder of gaitml-csv recordings with per-sample labels (walk, then run) and a manifest, no intervals files."""
    from gaitml.io import write_gaitml_csv, write_manifest

    rows = []
    for subject in ("Ann", "Bob"):
        for position in ("swinging-hand", "front-pocket"):
            rec = _swinging([0.0, 0.0, 1.0], n_s=40.0, position=position, subject=subject)
            half = rec.n_samples // 2
            labels = np.array(["walk"] * half + ["run"] * (rec.n_samples - half), dtype=object)
            name = f"{subject}-{position}.csv"
            write_gaitml_csv(rec.replace(labels=labels), root / name)
            rows.append({"file": name, "subject": subject, "session": f"{subject}-{position}", "position": position})
    write_manifest(rows, root)
    return root


def _csv_config(root, label="label", labels=None, **augment):
    raw = {
        "name": "aug",
        "seed": 3,
        "data": {"source": "folder", "path": str(root), "label": label, "group": "subject", "augment": augment},
        "features": {"set": "all52+gyro"},
    }
    if labels is not None:
        raw["data"]["labels"] = labels
    return parse_config(raw, base_dir=root)


def test_shared_time_never_trains_the_other_grips_stretches_as_a_class(tmp_path):
    """Per-sample labels without data.labels: a grip's 'unlabelled' stretches are left out, not learnt as a mode."""
    from gaitml.labels import UNLABELLED
    from gaitml.pipeline.runner import build_dataset

    root = _csv_folder(tmp_path)
    plain_cfg = _csv_config(root)
    plain = build_dataset(plain_cfg, prepare_data(plain_cfg, use_cache=False), use_cache=False)
    cfg = _csv_config(root, swing_turns=3, share_time=True)
    data = prepare_data(cfg, use_cache=False)
    ds = build_dataset(cfg, data, use_cache=False)
    assert UNLABELLED not in set(ds.y) and set(ds.y) == set(plain.y) == {"walk", "run"}
    assert abs(len(ds) - len(plain)) <= 0.1 * len(plain)  # every stretch once, in one grip
    assert any("another grip's stretches" in n for n in data.notes)
    with pytest.raises(ConfigError, match="remove 'unlabelled' from data.labels"):
        prepare_data(_csv_config(root, labels=["walk", "run", UNLABELLED], swing_turns=3, share_time=True), use_cache=False)


def test_shared_time_with_one_label_per_recording_is_refused(tmp_path):
    root = _csv_folder(tmp_path)
    with pytest.raises(ConfigError, match="share_time needs per-sample labels.*data.label = 'position'"):
        _csv_config(root, label="position", swing_turns=3, share_time=True)
    data = prepare_data(_csv_config(root, label="position", swing_turns=3), use_cache=False)  # whole copies: fine
    assert sum(bool(r.meta.get("augmented")) for r in data.recordings) == 6


def test_every_augment_position_must_match_a_recording(tmp_path):
    root = _csv_folder(tmp_path)
    with pytest.raises(ConfigError, match=r"has \['swinging_hand'\].*present \(with a gyroscope\): \['front-pocket', 'swinging-hand'\]"):
        prepare_data(_csv_config(root, swing_turns=2, positions=["swinging-hand", "swinging_hand"]), use_cache=False)


def test_augment_settings_that_cannot_apply_are_refused(tmp_path):
    root = _csv_folder(tmp_path)
    with pytest.raises(ConfigError, match="data.augment.share_time is set but data.augment.swing_turns = 0"):
        _csv_config(root, share_time=True)
    with pytest.raises(ConfigError, match="data.augment.positions is set but data.augment.swing_turns = 0"):
        _csv_config(root, positions=["front-pocket"])
    for aug in ({"share_time": True}, {"positions": ["front-pocket"]}):
        with pytest.raises(ConfigError, match="applies to data.source = 'folder'"):
            parse_config({"name": "x", "data": {"source": "simulated", "augment": aug}})
    # a sweep may turn the copies off while share_time stays set
    cfg = _csv_config(root, swing_turns=3, share_time=True)
    assert cfg.with_values({"data.augment.swing_turns": 0})["data"]["augment"]["swing_turns"] == 0


def test_cross_validation_scores_the_recordings_as_they_were_not_the_copies(tmp_path):
    """Copies train every fold; each fold is scored on its left-out people's original windows, with their full labels."""
    from gaitml.pipeline.runner import _evaluate_point, build_dataset

    root = _csv_folder(tmp_path)
    plain_cfg = _csv_config(root)
    plain = build_dataset(plain_cfg, prepare_data(plain_cfg, use_cache=False), use_cache=False)
    for aug in ({"swing_turns": 3, "share_time": True}, {"swing_turns": 2}):
        cfg = _csv_config(root, **aug)
        data = prepare_data(cfg, use_cache=False)
        point = _evaluate_point(cfg, data, False, "t")
        res, train, scored = point["cv"], point["dataset"], point["test_dataset"]
        assert res.before["n"] == len(plain) and int(res.folds["n_test"].sum()) == len(plain)
        assert not any("turned" in scored.recording_names[i] for i in res.predictions["recording"])
        assert sorted(scored.recording_names) == sorted(plain.recording_names)
        assert any("turned" in train.recording_names[i] for i in set(train.windows["recording"]))  # the copies were trained on
        if not aug.get("share_time"):
            assert int(res.folds["n_train"].sum()) == len(train) > len(plain)
        assert set(res.predictions["label"]) == {"walk", "run"} and len(train) >= len(plain) - 0.1 * len(plain)


def test_cross_validate_refuses_test_windows_of_groups_it_never_trained_on(tmp_path):
    from gaitml.evaluation.cv import cross_validate
    from gaitml.pipeline.runner import build_dataset

    root = _csv_folder(tmp_path)
    cfg = _csv_config(root)
    data = prepare_data(cfg, use_cache=False)
    ds = build_dataset(cfg, data, use_cache=False)
    data.groups = ["Cid" if g == "Bob" else g for g in data.groups]
    other = build_dataset(cfg, data, use_cache=False)
    with pytest.raises(InputError, match="test_dataset holds groups that dataset does not.*Cid"):
        cross_validate(ds, cfg["model"]["kind"], cfg["model"]["params"], progress=False, test_dataset=other)
    res = cross_validate(ds, cfg["model"]["kind"], cfg["model"]["params"], progress=False, test_dataset=ds)
    assert res.before["n"] == len(ds)
