"""The gravity feature frame (gaitml.features, frame='gravity'): rotation invariance, the physics of its sign, reference loop, CLI."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.features import (
    FEATURE_FRAMES,
    StreamingFeatureExtractor,
    extract_features,
    feature_names,
    features_from_arrays,
    gravity_frame_rotations,
    make_windows,
)
from gaitml.io import write_gaitml_csv
from gaitml.recording import Recording
from gaitml.simulate import simulate_dataset
from tests.reference.frame import reference_gravity_features, reference_rotation


@pytest.fixture(scope="module")
def sim():
    """One simulated subject, all five modes, tilted phone, gyro present."""
    return simulate_dataset(n_subjects=1, duration_s=60.0, pose="tilted", seed=21)[0]


def _rotated(rec: Recording, q: np.ndarray) -> Recording:
    return rec.replace(acc=rec.acc @ q.T, gyr=rec.gyr @ q.T, check_units=False)


@pytest.mark.parametrize("seed", range(6))
def test_features_unchanged_by_any_constant_phone_rotation(sim, seed):
    q = Rotation.random(random_state=seed).as_matrix()
    base = extract_features(sim, subset="all52+gyro", frame="gravity").to_numpy()
    rot = extract_features(_rotated(sim, q), subset="all52+gyro", frame="gravity").to_numpy()
    np.testing.assert_allclose(rot, base, rtol=1e-6, atol=1e-6)
    # the phone frame is not invariant (so the test above can fail)
    phone = extract_features(sim, subset="all52+gyro").to_numpy()
    phone_rot = extract_features(_rotated(sim, q), subset="all52+gyro").to_numpy()
    assert np.max(np.abs(phone_rot - phone)) > 1.0


@settings(max_examples=25, deadline=None)
@given(quat=st.lists(st.floats(-1, 1, allow_nan=False), min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1))
def test_rotation_invariance_property(sim, quat):
    q = Rotation.from_quat(np.asarray(quat) / np.linalg.norm(quat)).as_matrix()
    starts = np.arange(0, 600, 37)
    base = features_from_arrays(sim.acc[:700], sim.gyr[:700], 50.0, starts, 75, "all52+gyro", "gravity")
    rot = features_from_arrays(sim.acc[:700] @ q.T, sim.gyr[:700] @ q.T, 50.0, starts, 75, "all52+gyro", "gravity")
    np.testing.assert_allclose(rot, base, rtol=1e-6, atol=1e-6)


def test_rotations_are_proper_and_equal_the_loop_reference(sim):
    starts = np.arange(0, sim.n_samples - 75, 40)
    r = gravity_frame_rotations(sim.acc, starts, 75)
    np.testing.assert_allclose(r @ r.transpose(0, 2, 1), np.broadcast_to(np.eye(3), r.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=1e-12)
    want = np.array([reference_rotation(sim.acc[s : s + 75]) for s in starts])
    np.testing.assert_allclose(r, want, atol=1e-9)
    # z is the window's gravity estimate: the mean acceleration points along it (about g)
    mean = np.array([sim.acc[s : s + 75].mean(axis=0) for s in starts])
    np.testing.assert_allclose(np.einsum("kc,kc->k", r[:, 2], mean), np.linalg.norm(mean, axis=1), rtol=1e-12)


def test_forward_axis_follows_travel_by_physics():
    """Flat phone pointing forward: y of the frame is the phone's y when walking, opposite when running."""
    rec = simulate_dataset(n_subjects=1, duration_s=120.0, pose="flat", seed=11)[0]
    w = make_windows(rec, 1.5, 0.5, min_label_fraction=0.9)
    r = gravity_frame_rotations(rec.acc, w["start"].to_numpy(), 75)
    lab = w["label"].to_numpy()
    assert np.mean(r[lab == "walk", 1, 1] > 0.5) >= 0.8  # along the phone's forward axis
    assert np.mean(r[lab == "run", 1, 1] < -0.5) >= 0.8  # spring-mass gait: the opposite phase
    assert np.mean(r[lab == "backward", 1, 1] < 0.0) >= 0.8  # along the travel, i.e. behind the person (sway competes: sign only)


def test_gravity_features_equal_the_loop_reference(sim):
    starts = np.arange(0, 1200, 51)
    got = features_from_arrays(sim.acc, sim.gyr, 50.0, starts, 75, "all52+gyro", "gravity")
    want = reference_gravity_features(sim.acc, sim.gyr, starts, 75, "all52+gyro")
    mode_cols = [i for i, n in enumerate(feature_names("all52+gyro")) if n.endswith("__mode")]
    other = [i for i in range(got.shape[1]) if i not in mode_cols]
    np.testing.assert_allclose(got[:, other], want[:, other], rtol=1e-7, atol=1e-7)
    assert np.mean(np.isclose(got[:, mode_cols], want[:, mode_cols], atol=1e-9)) > 0.95
    # the magnitudes do not depend on the frame
    names = feature_names("all52+gyro")
    mag = [i for i, n in enumerate(names) if "_mag__" in n]
    phone = features_from_arrays(sim.acc, sim.gyr, 50.0, starts, 75, "all52+gyro")
    np.testing.assert_allclose(got[:, mag], phone[:, mag], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("subset", ["all52", "all52+gyro"])
def test_batch_equals_streaming_in_the_gravity_frame(sim, subset):
    batch = extract_features(sim, subset=subset, frame="gravity")
    assert batch.attrs["frame"] == "gravity"
    ext = StreamingFeatureExtractor(50.0, subset=subset, frame="gravity")
    rows, i, rng = [], 0, np.random.default_rng(2)
    while i < sim.n_samples:
        k = int(rng.choice([0, 1, 9, 64, 200]))
        rows.append(ext.push(sim.acc[i : i + k], sim.gyr[i : i + k] if "gyro" in subset else None))
        i += k
    np.testing.assert_allclose(np.concatenate(rows), batch.to_numpy(), rtol=1e-9, atol=1e-9)


def test_unknown_frame_is_refused(sim):
    assert FEATURE_FRAMES == ("phone", "gravity")
    with pytest.raises(InputError, match="unknown feature frame 'body'"):
        extract_features(sim, frame="body")
    with pytest.raises(InputError, match="unknown feature frame"):
        StreamingFeatureExtractor(50.0, frame="Gravity")


def test_cli_frame_option(sim, tmp_path, capsys):
    path = tmp_path / "in.csv"
    write_gaitml_csv(sim.slice(0, 1000), path)
    for frame in ("phone", "gravity"):
        assert main(["features", str(path), "--frame", frame, "--out", str(tmp_path / f"{frame}.csv")]) == 0
    import pandas as pd

    phone, grav = pd.read_csv(tmp_path / "phone.csv"), pd.read_csv(tmp_path / "gravity.csv")
    assert list(phone.columns) == list(grav.columns)
    assert not np.allclose(phone["acc_y__mean"], grav["acc_y__mean"])
    np.testing.assert_allclose(phone["acc_mag__var"], grav["acc_mag__var"], rtol=1e-9)
    # the gravity frame's z is up: its mean is |mean acc| (about g)
    assert np.all(grav["acc_z__mean"] > 8.0) and np.allclose(grav["acc_x__mean"], 0, atol=1e-9)
    capsys.readouterr()
    assert main(["features", str(path), "--frame", "sideways"]) == 2
    assert "--frame" in capsys.readouterr().err
