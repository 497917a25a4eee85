"""Tempo copies: a run replayed faster or slower (gaitml.pipeline.augment.tempo_copies), its physics, config and place in training."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import ConfigError, InputError
from gaitml.pipeline.augment import augmented_set, phone_up_gravity, rate_copies, tempo_copies, tempo_recording, without_copies
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import prepare_data
from gaitml.recording import Recording
from tests.pipeline.test_augment import _csv_config, _csv_folder, assert_same_domain

FS = 100.0
F_STRIDE = 1.4  # Hz, a running stride


def _motion(t):
    """A rigid motion with known derivatives: attitude Rz(psi) Rx(phi) and a forward path with a bounce and a sway.

    Returns the phone-to-world rotations, the body-frame angular rate (rad/s) and the world acceleration (m/s^2).
    """
    w = 2 * np.pi * F_STRIDE
    psi, dpsi = 0.3 * np.sin(w * t), 0.3 * w * np.cos(w * t)
    phi, dphi = 0.8 + 0.6 * np.sin(w * t + 0.5), 0.6 * w * np.cos(w * t + 0.5)
    rx = Rotation.from_rotvec(np.outer(phi, [1.0, 0.0, 0.0]))
    rot = Rotation.from_rotvec(np.outer(psi, [0.0, 0.0, 1.0])) * rx
    # R = Rz Rx: R^T dR/dt = Rx^T [psi' e_z]x Rx + [phi' e_x]x, so omega_b = Rx^T (0, 0, psi') + (phi', 0, 0)
    omega_b = rx.inv().apply(np.column_stack([0 * t, 0 * t, dpsi])) + np.column_stack([dphi, 0 * t, 0 * t])
    a_world = np.column_stack(
        [
            -0.05 * w**2 * np.sin(w * t),  # p_x = 1.5 t + 0.05 sin(w t)
            -0.03 * (w / 2) ** 2 * np.sin(w / 2 * t),  # p_y = 0.03 sin(w t / 2)
            -0.06 * (2 * w) ** 2 * np.sin(2 * w * t),  # p_z = 0.06 sin(2 w t)
        ]
    )
    return rot, omega_b, a_world


def _phone(t, speed=1.0):
    """What a phone on the motion ``x(speed t)`` reads at times ``t``: specific force (gravity up), angular rate, true up."""
    rot, omega_b, a_world = _motion(speed * t)
    up = rot.inv().apply(np.tile([0.0, 0.0, GRAVITY_MS2], (len(t), 1)))
    acc = rot.inv().apply(speed**2 * a_world) + up
    return acc, speed * omega_b, up


def _run_recording(n_s=40.0):
    t = np.arange(0.0, n_s, 1 / FS)
    acc, gyr, up = _phone(t)
    labels = np.where(t < n_s / 2, "walk", "run").astype(object)
    rec = Recording(acc=acc, gyr=gyr, sampling_rate_hz=FS, labels=labels, meta={"id": "syn", "subject": "Ann", "position": "pocket"})
    return rec, up


@pytest.mark.parametrize("s", [0.8, 0.87, 1.15, 1.25])
def test_a_tempo_copy_is_the_motion_replayed_at_that_tempo(s):
    """With the true gravity, the copy equals the phone's reading of x(s t) up to the interpolation (and low-pass) error."""
    rec, up = _run_recording()
    c = tempo_recording(rec, s, up)
    assert c.n_samples == int(np.floor((rec.n_samples - 1) / s)) + 1 and c.sampling_rate_hz == FS
    t_new = np.arange(c.n_samples) / FS
    acc, gyr, _ = _phone(t_new, speed=s)
    inner = slice(int(2 * FS), c.n_samples - int(2 * FS))  # the zero-phase low-pass's edges left out (s > 1)
    # interpolation error of a smooth signal sampled at 100 Hz: h^2/8 max|x''|, a few hundredths here
    assert np.max(np.abs(c.gyr[inner] - gyr[inner])) < 0.02 * np.max(np.abs(gyr))
    assert np.max(np.abs(c.acc[inner] - acc[inner])) < 0.02 * np.max(np.abs(acc - _phone(t_new, speed=s)[2]))
    # and the copy is not the original: the angular rate and the linear acceleration are scaled
    assert np.isclose(np.percentile(np.abs(c.gyr), 99) / np.percentile(np.abs(rec.gyr), 99), s, rtol=0.03)
    # labels follow the time axis: the change at 20 s of the original is at 20 / s in the copy
    first_run = int(np.argmax(c.labels.astype(str) == "run"))
    assert abs(first_run / FS - 20.0 / s) <= 1.5 / FS
    assert c.meta["augmented"] == f"tempo {s:g}x" and c.meta["augment_in_domain"] and c.meta["augment_tempo"] == s
    assert c.reference == {} and rec.meta.get("augmented") is None


def test_the_attitude_filters_gravity_follows_the_turns_and_the_copy_with_it():
    """The default gravity (the attitude filter's) is within 10 deg of the truth here, and the copy close to the true one.

    The filter's tilt is pulled towards the low-passed specific force, whose mean in a phone turning with the stride is
    not exactly gravity: about 6 deg off on this motion (5 deg median on the tyrex pocket runs whose motion capture
    matches the gyroscope, experiments/scripts/tempo_gravity.py). A low-pass of the accelerometer is 25-40 deg off.
    """
    rec, up = _run_recording()
    g_b = phone_up_gravity(rec)
    late = slice(int(10 * FS), None)  # after the filter's start
    ang = np.degrees(np.arccos(np.clip(np.sum(g_b * up, axis=1) / GRAVITY_MS2**2, -1, 1)))
    assert np.percentile(ang[late], 95) < 10.0
    # a low-pass of the accelerometer cannot follow the 0.6 rad turns within a stride: much further off
    from gaitml.signal import gravity_direction

    lp = gravity_direction(rec.acc, FS, cutoff_hz=0.3)
    ang_lp = np.degrees(np.arccos(np.clip(np.sum(lp * up, axis=1) / GRAVITY_MS2, -1, 1)))
    assert np.percentile(ang_lp[late], 95) > 3 * np.percentile(ang[late], 95)
    c = tempo_recording(rec, 1.15)
    exact = tempo_recording(rec, 1.15, up)
    inner = slice(int(10 * FS), c.n_samples - int(2 * FS))
    err = np.linalg.norm(c.acc[inner] - exact.acc[inner], axis=1)
    # the error is |1 - s^2| times the gravity error: a few percent of the copy's linear acceleration
    lin_rms = 1.15**2 * np.sqrt(np.mean(np.sum((rec.acc - up) ** 2, axis=1)))
    assert np.percentile(err, 95) < 0.05 * lin_rms
    np.testing.assert_allclose(c.gyr, exact.gyr)  # the angular rate needs no gravity


def test_tempo_copies_pick_the_running_recordings_and_refuse_bad_factors():
    rec, _ = _run_recording(n_s=12.0)
    walk = rec.replace(labels=np.full(rec.n_samples, "walk", dtype=object))
    no_gyr = rec.replace(gyr=None)
    out = tempo_copies([walk, rec, no_gyr], [0.87, 1.15])
    assert [c.meta["augment_tempo"] for c in out] == [0.87, 1.15] and all(c.meta["id"].startswith("syn") for c in out)
    assert len(tempo_copies([walk], [1.15], labels=["walk"])) == 1
    for bad, msg in (([1.0], "a tempo factor of 1"), ([2.5], "between 0.5 and 2"), ([0.9, 0.9], "twice"), (["x"], "is a number")):
        with pytest.raises(InputError, match=msg):
            tempo_copies([rec], bad)
    with pytest.raises(InputError, match="needs the gyroscope"):
        phone_up_gravity(no_gyr)
    with pytest.raises(InputError, match="accelerometer's shape"):
        tempo_recording(rec, 1.15, np.zeros((3, 3)))


def test_turned_flipped_and_rate_copies_of_a_tempo_copy_leave_the_domain_record():
    rec, _ = _run_recording(n_s=12.0)
    c = tempo_copies([rec], [1.15])[0]
    flipped = augmented_set([rec, c], 0, flips=["y"], flip_positions=["pocket"])[1]
    assert [f.meta["augmented"] for f in flipped] == ["flipped about y", "flipped about y, tempo 1.15x"]
    low = rate_copies([c], [20.0])[0]
    assert low.meta["augmented"] == "tempo 1.15x, recorded at 20 Hz"
    recs = [rec, c, *flipped, low]
    kept, groups = without_copies(recs, list(range(len(recs))), keep_in_domain=True)
    assert kept == [rec, c] and groups == [0, 1]
    assert without_copies(recs, list(range(len(recs))))[0] == [rec]


def test_tempo_settings_are_validated(tmp_path):
    root = _csv_folder(tmp_path)
    for bad, msg in (
        ([1], "has 1, not a tempo factor"),
        ([0.3], "has 0.3, not a tempo factor"),
        ([0.9, 0.9], "lists a factor twice"),
        (["fast"], "must list tempo factors"),
    ):
        with pytest.raises(ConfigError, match=f"data.augment.tempo = .* {msg}"):
            _csv_config(root, tempo=bad)
    with pytest.raises(ConfigError, match="tempo_labels is set but data.augment.tempo is empty"):
        _csv_config(root, tempo_labels=["walk"])
    with pytest.raises(ConfigError, match="tempo_labels is empty"):
        _csv_config(root, tempo=[1.15], tempo_labels=[])
    with pytest.raises(ConfigError, match="data.augment.tempo applies to data.source = 'folder'"):
        parse_config({"name": "x", "data": {"source": "simulated", "augment": {"tempo": [1.15]}}})
    with pytest.raises(ConfigError, match=r"tempo_labels = \['jog'\] matches no recording with a gyroscope.*labels present: run, walk"):
        prepare_data(_csv_config(root, tempo=[1.15], tempo_labels=["jog"]), use_cache=False)
    assert "tempo" not in _csv_config(root, swing_turns=1).resolved()["data"]["augment"]
    cfg = _csv_config(root, tempo=[0.87, 1.15])
    assert cfg.resolved()["data"]["augment"]["tempo"] == [0.87, 1.15]
    data = prepare_data(cfg, use_cache=False)
    tempo = [r for r in data.recordings if r.meta.get("augment_tempo")]
    assert len(tempo) == 8 and len(data.recordings) == 12  # every recording holds a run stretch: 4 x 2 copies
    assert sorted(data.groups[4:]) == ["Ann"] * 4 + ["Bob"] * 4  # in their recording's group
    assert any("8 tempo copies of the 4 recording(s) labelled run" in n for n in data.notes)


def test_cross_validation_trains_on_tempo_copies_but_scores_the_recordings(tmp_path):
    from gaitml.pipeline.runner import _evaluate_point, build_dataset

    root = _csv_folder(tmp_path)
    plain_cfg = _csv_config(root)
    plain = build_dataset(plain_cfg, prepare_data(plain_cfg, use_cache=False), use_cache=False)
    cfg = _csv_config(root, tempo=[0.87, 1.15])
    point = _evaluate_point(cfg, prepare_data(cfg, use_cache=False), False, "t")
    res, train, scored = point["cv"], point["dataset"], point["test_dataset"]
    assert res.before["n"] == len(plain) and int(res.folds["n_test"].sum()) == len(plain)
    assert not any("tempo" in scored.recording_names[i] for i in res.predictions["recording"])
    assert any("tempo" in train.recording_names[i] for i in set(train.windows["recording"])) and len(train) > len(plain)


def test_the_domain_record_holds_the_tempo_copies_but_not_their_flips(tmp_path):
    """Tempo copies are fitted into the domain record as if they were recordings; their flipped copies are not."""
    from gaitml.models import make_model
    from gaitml.pipeline.runner import PreparedData, build_dataset, fit_training_domain

    root = _csv_folder(tmp_path)

    def domain(cfg, data):
        ds = build_dataset(cfg, data, use_cache=False)
        model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed).fit(ds.inputs("features"), ds.y)
        return fit_training_domain(cfg, data, ds, model)

    cfg0 = _csv_config(root)
    d0 = domain(cfg0, prepare_data(cfg0, use_cache=False))
    cfg1 = _csv_config(root, tempo=[0.87, 1.15])
    data1 = prepare_data(cfg1, use_cache=False)
    d1 = domain(cfg1, data1)
    # the same recordings with the copies' marks removed: plain recordings, all in the record
    unmarked = [r.replace(meta={k: v for k, v in r.meta.items() if not k.startswith("augment")}) for r in data1.recordings]
    d_plain = domain(cfg0, PreparedData(unmarked, data1.groups, [], keep_labels=data1.keep_labels))
    assert_same_domain(d1, d_plain)
    assert d1.to_arrays().keys() == d0.to_arrays().keys()
    assert any(not np.allclose(v, d0.to_arrays()[k]) for k, v in d1.to_arrays().items() if v.shape == d0.to_arrays()[k].shape)
    cfg2 = _csv_config(root, tempo=[0.87, 1.15], flips=["y"], flip_positions=["front-pocket"])
    data2 = prepare_data(cfg2, use_cache=False)
    assert sum("flipped about y, tempo" in r.meta.get("augmented", "") for r in data2.recordings) == 4
    assert_same_domain(domain(cfg2, data2), d1)


def test_tempo_copies_by_position_and_out_of_the_domain_record():
    rec, _ = _run_recording(n_s=12.0)
    hand = rec.replace(meta={**rec.meta, "position": "hand", "id": "hand"})
    out = tempo_copies([hand, rec], [0.87, 1.15], positions=["pocket"], in_domain=False)
    assert [c.meta["id"] for c in out] == ["syn [tempo 0.87x]", "syn [tempo 1.15x]"]  # the pocket recording only
    assert all("augment_in_domain" not in c.meta and c.meta["augmented"].startswith("tempo") for c in out)
    assert len(tempo_copies([hand, rec], [1.15])) == 2  # positions None: any position
    assert tempo_copies([hand], [1.15], positions=["pocket"]) == []
    # out of the record: what the domain is fitted on is the recordings alone, as without copies
    kept, _ = without_copies([rec, *out], [0, 1, 2], keep_in_domain=True)
    assert kept == [rec]
    # the same samples either way: only the mark differs
    inside = tempo_copies([rec], [1.15])[0]
    np.testing.assert_array_equal(inside.acc, out[1].acc)
    assert inside.meta["augment_in_domain"] is True


def test_tempo_positions_and_in_domain_are_validated(tmp_path):
    root = _csv_folder(tmp_path)  # swinging-hand and front-pocket recordings, each with a run stretch
    with pytest.raises(ConfigError, match="tempo_positions is set but data.augment.tempo is empty"):
        _csv_config(root, tempo_positions=["front-pocket"])
    with pytest.raises(ConfigError, match="tempo_in_domain is set but data.augment.tempo is empty"):
        _csv_config(root, tempo_in_domain=False)
    with pytest.raises(ConfigError, match="data.augment.tempo_positions = .* lists an item twice"):
        _csv_config(root, tempo=[1.15], tempo_positions=["front-pocket", "front-pocket"])
    with pytest.raises(ConfigError, match="data.augment.tempo_positions applies to data.source = 'folder'"):
        parse_config({"name": "x", "data": {"source": "simulated", "augment": {"tempo_positions": ["pocket"]}}})
    with pytest.raises(
        ConfigError, match=r"tempo_positions has \['pocket'\], which matches no recording labelled run.*front-pocket, swinging-hand"
    ):
        prepare_data(_csv_config(root, tempo=[1.15], tempo_positions=["pocket"]), use_cache=False)
    # defaults are not written: a config without the keys resolves as before
    aug = _csv_config(root, tempo=[1.15]).resolved()["data"]["augment"]
    assert "tempo_positions" not in aug and "tempo_in_domain" not in aug
    cfg = _csv_config(root, tempo=[0.87, 1.15], tempo_positions=["front-pocket"], tempo_in_domain=False)
    aug = cfg.resolved()["data"]["augment"]
    assert aug["tempo_positions"] == ["front-pocket"] and aug["tempo_in_domain"] is False
    data = prepare_data(cfg, use_cache=False)
    tempo = [r for r in data.recordings if r.meta.get("augment_tempo")]
    assert len(tempo) == 4 and {r.meta["position"] for r in tempo} == {"front-pocket"}  # 2 people x 2 factors
    assert not any(r.meta.get("augment_in_domain") for r in data.recordings)
    assert any(
        "4 tempo copies of the 2 recording(s) labelled run in front-pocket" in n and "not in the domain record" in n for n in data.notes
    )


def test_tempo_copies_out_of_the_domain_record_leave_it_as_without_them(tmp_path):
    """With tempo_in_domain = false the record is the one fitted without any tempo copy; the classifier still trains on them."""
    from gaitml.models import make_model
    from gaitml.pipeline.runner import build_dataset, fit_training_domain

    root = _csv_folder(tmp_path)

    def fitted(cfg):
        data = prepare_data(cfg, use_cache=False)
        ds = build_dataset(cfg, data, use_cache=False)
        model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed).fit(ds.inputs("features"), ds.y)
        return fit_training_domain(cfg, data, ds, model), len(ds)

    d0, n0 = fitted(_csv_config(root))
    d1, n1 = fitted(_csv_config(root, tempo=[0.87, 1.15], tempo_positions=["front-pocket"], tempo_in_domain=False))
    assert n1 > n0  # the classifier's windows hold the copies
    assert_same_domain(d1, d0)
    assert np.isclose(d1.distance_threshold, d0.distance_threshold, rtol=1e-9)
    d2, _ = fitted(_csv_config(root, tempo=[0.87, 1.15], tempo_positions=["front-pocket"]))  # in the record: it moves
    assert any(not np.allclose(v, d0.to_arrays()[k]) for k, v in d2.to_arrays().items() if v.shape == d0.to_arrays()[k].shape)


def test_the_training_note_counts_the_real_recordings_turned_apart_from_their_tempo_copies(tmp_path):
    """The swing-turn note names how many recordings were turned: the real ones, and the tempo copies among them."""
    root = _csv_folder(tmp_path)  # 2 real swinging-hand recordings, each with a run stretch
    plain = prepare_data(_csv_config(root, swing_turns=3), use_cache=False)
    assert any("6 copies of the 2 real recording(s) in ['swinging-hand']" in n for n in plain.notes)
    data = prepare_data(_csv_config(root, swing_turns=3, tempo=[0.87, 1.15]), use_cache=False)
    note = next(n for n in data.notes if "turned about its swing axis" in n)
    assert "18 copies of the 2 real recording(s) and their 4 tempo copies in ['swinging-hand']" in note
