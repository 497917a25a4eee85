"""The forward-vector group W1..W3 (gaitml.features._forward, opt-in sets all52+fwd / all52+gyro+fwd).

What must hold: the vector points along the direction of travel of a walk-like window (the horizontal
acceleration following d/dt of the vertical one), a window played backwards in time gives exactly the
opposite vector while every one of the 52 accelerometer features stays the same, a constant rotation of
the phone turns the vector with it, the scale of the signal and its sampling rate do not matter, and on
the simulator a phone held flat reads walking and backward walking with opposite signs along its y.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitml.errors import InputError
from gaitml.features import (
    FEATURE_SETS,
    StreamingFeatureExtractor,
    extract_features,
    feature_names,
    features_from_arrays,
    forward_vectors,
    make_windows,
    resolve_subset,
    uses_forward,
    uses_forward_face,
    uses_gyro,
)
from gaitml.recording import Recording

FWD = ["acc_x__fwd", "acc_y__fwd", "acc_z__fwd"]


def _walk(n: int = 1500, fs: float = 50.0, step_hz: float = 1.8, seed: int = 0, forward=(0.0, 1.0, 0.0)) -> np.ndarray:
    """A walk-like phone-flat signal: vertical bounce at the step frequency, the forward acceleration a quarter
    step behind it (following its rate: fastest at the vertical peak), lateral sway at the stride frequency, noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    w = 2 * np.pi * step_hz
    vert = 2.0 * np.cos(w * t)
    fwd = -1.0 * np.sin(w * t)  # d/dt cos = -sin: the forward acceleration follows the vertical one's rate
    lat = 0.6 * np.sin(w / 2 * t + 0.4)
    f = np.asarray(forward, float) / np.linalg.norm(forward)
    right = np.cross(f, [0.0, 0.0, 1.0])
    acc = np.outer(fwd, f) + np.outer(lat, right) + np.outer(9.81 + vert, [0.0, 0.0, 1.0])
    return acc + rng.normal(0, 0.3, (n, 3))


def _starts(n: int, length: int, hop: int) -> np.ndarray:
    return np.arange(0, n - length + 1, hop)


def test_the_sets_are_opt_in_and_named():
    assert FEATURE_SETS["all52+fwd"][-3:] == tuple(FWD) and len(FEATURE_SETS["all52+fwd"]) == 55
    assert FEATURE_SETS["all52+gyro+fwd"][:104] == FEATURE_SETS["all52+gyro"] and len(FEATURE_SETS["all52+gyro+fwd"]) == 107
    assert not any(n.endswith("__fwd") for n in FEATURE_SETS["all52+gyro"] + FEATURE_SETS["all52"])
    assert uses_forward("all52+gyro+fwd") and uses_gyro("all52+gyro+fwd") and not uses_gyro("all52+fwd")
    assert not uses_forward("all52+gyro") and not uses_forward("all")
    assert uses_forward("all52+gyro+fwdface") and uses_forward_face("all52+fwdface") and not uses_forward_face("all52+fwd")
    assert FEATURE_SETS["all52+gyro+fwdface"][-3:] == ("acc_x__fwdface", "acc_y__fwdface", "acc_z__fwdface")
    with pytest.raises(InputError, match="unknown feature subset"):
        resolve_subset("all52+fwd+gyro")


def test_a_walk_points_along_its_direction_of_travel():
    acc = _walk()
    v = forward_vectors(acc, 50.0, _starts(len(acc), 75, 37), 75)
    assert np.all(np.linalg.norm(v, axis=1) <= 1.0 + 1e-12)
    assert np.all(v[:, 1] > 0.7), v[:, 1].min()  # along +y, close to the Cauchy-Schwarz bound
    assert np.all(np.abs(v[:, 0]) < 0.3) and np.all(np.abs(v[:, 2]) < 0.05)  # no lateral part
    starts = _starts(len(acc), 75, 37)
    up = np.array([acc[s : s + 75].mean(axis=0) for s in starts])
    np.testing.assert_allclose(np.einsum("kc,kc->k", v, up), 0.0, atol=1e-9)  # horizontal: normal to the window's gravity
    back = forward_vectors(_walk(forward=(0.0, -1.0, 0.0)), 50.0, _starts(len(acc), 75, 37), 75)
    assert np.all(back[:, 1] < -0.7)  # travelling towards -y


def test_time_reversal_flips_the_vector_and_leaves_the_52_accelerometer_features():
    """The reason for the group: played backwards, a window gives -F exactly, while F1..F52 do not move."""
    acc = _walk(seed=3)
    n, length = len(acc), 75
    starts = _starts(n, length, 37)
    fwd = features_from_arrays(acc, None, 50.0, starts, length, "all52+fwd")
    rev = features_from_arrays(acc[::-1].copy(), None, 50.0, n - length - starts, length, "all52+fwd")
    np.testing.assert_allclose(rev[:, 52:], -fwd[:, 52:], atol=1e-12)
    np.testing.assert_allclose(rev[:, :52], fwd[:, :52], rtol=1e-9, atol=1e-9)
    assert np.all(fwd[:, 53] > 0.7) and np.all(rev[:, 53] < -0.7)


@pytest.mark.parametrize("seed", range(4))
def test_a_constant_rotation_of_the_phone_turns_the_vector_with_it(seed):
    acc = _walk(seed=seed)
    q = Rotation.random(random_state=seed).as_matrix()
    starts = _starts(len(acc), 75, 37)
    v = forward_vectors(acc, 50.0, starts, 75)
    vq = forward_vectors(acc @ q.T, 50.0, starts, 75)
    np.testing.assert_allclose(vq, v @ q.T, atol=1e-9)


def test_the_face_up_weight_keeps_the_vector_in_the_hand_and_drops_it_upright():
    """W4..W6 = W1..W3 times max(0, up_z): unchanged lying flat, scaled by the tilt's cosine held tilted, 0 upright
    (a pocket, a swinging hand, at the ear), where the phone's axes are not tied to the walker's forward."""
    acc = _walk(seed=4)
    starts = _starts(len(acc), 75, 37)
    plain = forward_vectors(acc, 50.0, starts, 75)
    up_z = np.array([acc[s : s + 75].mean(axis=0)[2] / np.linalg.norm(acc[s : s + 75].mean(axis=0)) for s in starts])
    np.testing.assert_allclose(forward_vectors(acc, 50.0, starts, 75, face_up=True), plain * up_z[:, None], atol=1e-12)
    for deg, weight in ((40.0, np.cos(np.radians(40.0))), (90.0, 0.0), (150.0, 0.0)):
        q = Rotation.from_euler("x", deg, degrees=True).as_matrix()  # pitched about the phone's x: top up
        tilted = acc @ q  # the phone turned by q^T: the same motion read in its axes
        v = forward_vectors(tilted, 50.0, starts, 75, face_up=True)
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), np.linalg.norm(plain, axis=1) * weight, atol=0.03)
    x = features_from_arrays(acc, None, 50.0, starts, 75, "all52+fwdface")
    np.testing.assert_allclose(x[:, 52:], plain * up_z[:, None], atol=1e-12)


def test_scale_and_sampling_rate_cancel():
    fs = 100.0
    acc = _walk(n=3000, fs=fs, seed=5)
    starts = _starts(len(acc), 150, 75)
    v = forward_vectors(acc, fs, starts, 150)
    np.testing.assert_allclose(forward_vectors(1.7 * acc, fs, starts, 150), v, atol=1e-12)
    # the same motion at 50 Hz (every other sample): the same direction, in-band content is below 3 Hz
    v50 = forward_vectors(acc[::2], 50.0, starts // 2, 75)
    assert np.all(v50[:, 1] > 0.7) and np.all(v[:, 1] > 0.7)


def test_no_lag_no_vector():
    """A bounce without a forward acceleration in quadrature, a window too short for the band, a constant window: 0 or near it."""
    fs, n = 50.0, 1500
    t = np.arange(n) / fs
    rng = np.random.default_rng(2)
    in_phase = np.column_stack([0.0 * t, np.cos(2 * np.pi * 1.8 * t), 9.81 + 2 * np.cos(2 * np.pi * 1.8 * t)])
    v = forward_vectors(in_phase + rng.normal(0, 0.05, (n, 3)), fs, _starts(n, 75, 37), 75)
    assert np.all(np.abs(v[:, 1]) < 0.15)  # in phase with the vertical acceleration itself, not its rate
    assert np.all(forward_vectors(_walk(), fs, _starts(n, 15, 15), 15) == 0.0)  # 0.3 s: no coefficient in 0.5-3 Hz
    still = np.tile([0.0, 0.0, 9.81], (200, 1))
    assert np.all(forward_vectors(still, fs, [0, 100], 75) == 0.0)


def test_the_sampling_rate_is_required():
    acc = _walk(n=200)
    with pytest.raises(InputError, match="sampling rate"):
        features_from_arrays(acc, None, None, [0], 75, "all52+fwd")
    assert features_from_arrays(acc, None, None, [0], 75, "all52").shape == (1, 52)  # the 52 do not need it


def test_gyro_set_needs_a_gyroscope_in_batch_and_stream():
    acc = _walk(n=200)
    rec = Recording.from_arrays(acc, 50.0)
    with pytest.raises(InputError, match="gyroscope"):
        extract_features(rec, subset="all52+gyro+fwd")
    with pytest.raises(InputError, match="gyroscope"):
        StreamingFeatureExtractor(50.0, subset="all52+gyro+fwd").push(acc[:10])
    assert list(extract_features(rec, subset="all52+fwd").columns) == feature_names("all52+fwd")


@pytest.fixture(scope="module")
def flat_walker():
    from gaitml.simulate import simulate_dataset

    return simulate_dataset(n_subjects=1, duration_s=150.0, modes=("walk", "backward"), pose="flat", seed=2024)[0]


def test_simulated_phone_held_flat_reads_walk_and_backward_with_opposite_signs(flat_walker):
    """The simulator's hand-flat walker (phone y = the walker's forward): walking along +y, backward walking along -y,
    in most windows (the held-out study gives 0.94-0.95 for the unfiltered sign; a floor, not the figure)."""
    rec = flat_walker
    win = make_windows(rec, 1.5, 0.5, min_label_fraction=0.9)
    f = extract_features(rec, win, subset="all52+fwd")
    y = f["acc_y__fwd"].to_numpy()
    lab = win["label"].astype(str).to_numpy()
    assert (lab == "walk").sum() > 20 and (lab == "backward").sum() > 20
    assert np.mean(y[lab == "walk"] > 0) >= 0.85
    assert np.mean(y[lab == "backward"] < 0) >= 0.85


def test_a_saved_model_on_the_set_reads_the_same_rows_whole_chunked_and_streamed(tmp_path):
    """A model trained on all52+gyro+fwd through the library's path: saved and loaded, its whole-file, chunked and
    streamed rows agree, and its portable export states how the forward vector is computed."""
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.models import LinearOVOSVM, build_window_dataset, export_json, load_model, model_inputs, predict_recording, save_model
    from gaitml.models._predict import model_view
    from tests.models.synth import synth_recording, synth_set

    fset = "all52+gyro+fwd"
    modes = ("walk", "backward", "side_left")
    recs = synth_set(3, modes=modes, seconds_per_mode=12.0, gyr=True)
    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, feature_set=fset)
    assert ds.inputs("features").shape[1] == 107
    info = {
        "model_kind": "linear-ovo-svm",
        "input_kind": "features",
        "feature_set": fset,
        "feature_names": feature_names(fset),
        "window": {"length_s": 1.5, "overlap": 0.5},
        "sampling_rate_hz": 50.0,
        "labels": sorted(set(ds.y)),
    }
    save_model(tmp_path / "m", LinearOVOSVM().fit(ds.inputs("features"), ds.y), info)
    model = load_model(tmp_path / "m")
    rec = synth_recording(9, modes=modes, seconds_per_mode=20.0, gyr=True)
    path = tmp_path / "rec.csv"
    write_gaitml_csv(rec, path)
    rec = read_recording(path)
    whole = predict_recording(model, rec)
    assert np.mean(whole["mode"] == whole["label"]) > 0.8
    chunked = long_predict(model, path, chunk_s=15.0, progress=False)
    assert whole["mode"].tolist() == chunked["mode"].tolist()
    ext = StreamingFeatureExtractor.for_model(model)
    rows = [ext.push(rec.acc[i : i + 29], rec.gyr[i : i + 29]) for i in range(0, rec.n_samples, 29)]
    w = make_windows(rec, 1.5, 0.5, min_label_fraction=0.0).reset_index(drop=True)
    np.testing.assert_allclose(np.vstack(rows), model_inputs(model, model_view(model, rec)[0], w), rtol=1e-9, atol=1e-9)
    spec = export_json(model)["features"]
    assert "forward_vector" in spec["conventions"] and spec["conventions"]["forward_vector"]["band_hz"] == [0.5, 3.0]
    assert [f["paper_number"] for f in spec["features"][-3:]] == [None, None, None]


def test_a_window_with_a_nan_sample_has_no_vector_as_the_52_statistics():
    """A NaN sample makes the window's statistics NaN (features_from_arrays does not refuse it); the forward vector is
    NaN there too, not the 0 of a window without a lag (which a model would read as a real, calm window)."""
    fs, n = 50.0, 400
    acc = _walk(n=n, fs=fs)
    acc[100, 0] = np.nan
    starts = _starts(n, 75, 37)
    bad = (starts <= 100) & (100 < starts + 75)
    for subset in ("all52+fwd", "all52+fwdface"):
        x = features_from_arrays(acc, None, fs, starts, 75, subset)
        assert np.isnan(x[bad, 0]).all()  # acc_x__mean: the 52 statistics see the NaN
        assert np.isnan(x[bad, -3:]).all() and np.isfinite(x[~bad, -3:]).all()


def test_windows_too_short_for_the_band_are_refused_not_read_as_zero():
    """Under 1/3 s no Fourier coefficient of the window lies in 0.5-3 Hz and every vector would be 0 (no lag): a window
    of such a length is refused with the fix (gaitml features, training and predict read windows through extract_features)."""
    rec = Recording.from_arrays(_walk(n=600), 50.0)
    with pytest.raises(InputError, match=r"forward vector.*--window-s|window-s.*forward vector"):
        extract_features(rec, subset="all52+fwdface", length_s=0.3)
    with pytest.raises(InputError, match="forward vector"):
        StreamingFeatureExtractor(50.0, length_s=0.3, subset="all52+fwd")
    assert extract_features(rec, subset="all52", length_s=0.3).shape[1] == 52  # the 52 read any window
    f = extract_features(rec, subset="all52+fwd", length_s=0.5)  # 0.5 s: 2 Hz is in the band
    assert (np.abs(f["acc_y__fwd"].to_numpy()) > 0.5).mean() > 0.8


@pytest.mark.parametrize("face_up", [False, True])
def test_a_few_windows_read_as_in_a_long_batch(face_up):
    """Up to a few windows (a stream's new window) are gathered by indexing, more through a strided view: the same
    rows either way, a window holding a NaN sample included (the streamed rows are the whole file's)."""
    from gaitml.features._forward import _FEW_WINDOWS

    fs, n, length = 50.0, 2400, 75
    rot = Rotation.from_rotvec([0.4, -0.9, 0.3]).as_matrix()
    acc = _walk(n=n, fs=fs, seed=3) @ rot.T + np.random.default_rng(3).normal(0, 0.5, (n, 3))
    acc[500, 1] = np.nan
    starts = _starts(n, length, 37)
    assert len(starts) > _FEW_WINDOWS
    batch = forward_vectors(acc, fs, starts, length, face_up=face_up)
    assert np.isnan(batch).any() and np.isfinite(batch).any()
    for k in (1, 3, _FEW_WINDOWS):
        for i in range(0, len(starts) - k + 1, 7):
            few = forward_vectors(acc, fs, starts[i : i + k], length, face_up=face_up)
            np.testing.assert_allclose(few, batch[i : i + k], rtol=0, atol=1e-13, equal_nan=True)
