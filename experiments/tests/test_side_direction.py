"""experiments.scripts.side_direction: the walker's forward axis from walking and a side step's direction in it."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.spatial.transform import Rotation

from experiments.scripts.side_direction import body_frame_side_directions, direction_table, score_recording, window_vectors
from experiments.tests.conftest import ROOT
from gaitml.errors import InputError

FS = 50.0
N = 75  # one 1.5 s window at 50 Hz
G = 9.81


def _body_window(kind: str, rng, *, phase=0.0, direction=1.0) -> np.ndarray:
    """One window of body-frame acceleration (right, forward, up; gravity included), noise of 0.1 m/s^2.

    ``walk``: vertical peaks at heel strike where the forward speed is highest (forward acceleration -sin), sway at
    half the step frequency; ``backward`` the same along -forward; ``side``: the lateral acceleration against the
    motion (``direction`` +1 right, -1 left) when the vertical one peaks.
    """
    t = np.arange(N) / FS
    w = 2 * np.pi * 1.8 * t + phase
    a = np.zeros((N, 3))
    a[:, 2] = G + 2.0 * np.cos(w)
    if kind == "walk":
        a[:, 1] = -1.5 * np.sin(w)
        a[:, 0] = 0.8 * np.sin(0.5 * w)
    elif kind == "backward":
        a[:, 1] = 1.5 * np.sin(w)
    elif kind == "side":
        a[:, 0] = -direction * 2.0 * np.cos(w)
    return a + 0.1 * rng.standard_normal((N, 3))


def _in_phone(windows, mount: np.ndarray) -> np.ndarray:
    """Body-frame windows read by a phone whose axes are the columns of ``mount`` (body coordinates)."""
    return np.concatenate([w @ mount for w in windows])


def _decide(acc, kinds, *, min_walk=4, scope="recording"):
    starts = np.arange(len(kinds)) * N
    up, fw, lat = window_vectors(acc, starts, starts + N)
    modes = np.array(["walk" if k == "walk" else "side_left" for k in kinds])
    unsure = np.array([k.startswith("side") for k in kinds])
    return body_frame_side_directions(modes, unsure, modes == "walk", up, fw, lat, min_walk_windows=min_walk, scope=scope)


def test_forward_vector_points_forward_in_walking_and_back_in_backward_walking():
    rng = np.random.default_rng(0)
    mount = Rotation.from_euler("xyz", [100, -20, 35], degrees=True).as_matrix()  # a phone upright at a slant
    fwd_phone = mount.T @ np.array([0.0, 1.0, 0.0])
    for kind, sign in (("walk", 1.0), ("backward", -1.0)):
        acc = _in_phone([_body_window(kind, rng, phase=p) for p in (0.0, 1.0, 2.0)], mount)
        _, fw, _ = window_vectors(acc, [0, N, 2 * N], [N, 2 * N, 3 * N])
        for f in fw:
            cos = sign * float(f @ fwd_phone) / np.linalg.norm(f)
            assert cos > np.cos(np.radians(10.0)), (kind, cos)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_side_step_direction_survives_the_phone_placement(seed):
    """Any rigid placement (screen in or out, upside down, either way about gravity) gives the same directions:
    the phone-frame x axis would flip with it."""
    rng = np.random.default_rng(seed)
    kinds = ["walk"] * 5 + ["side_right", "side_left", "side_right"]
    body = [_body_window("walk", rng, phase=i) for i in range(5)]
    body += [_body_window("side", rng, direction=1.0), _body_window("side", rng, direction=-1.0), _body_window("side", rng, direction=1.0)]
    for mount in (np.eye(3), np.diag([-1.0, 1.0, -1.0]), Rotation.random(random_state=seed).as_matrix()):
        modes, decided = _decide(_in_phone(body, mount), kinds)
        assert decided.tolist() == [False] * 5 + [True] * 3
        assert modes[5:].tolist() == ["side_right", "side_left", "side_right"]


def test_too_little_walking_or_none_before_keeps_the_window_unsure():
    rng = np.random.default_rng(4)
    mount = np.eye(3)
    kinds = ["side_right"] + ["walk"] * 4
    body = [_body_window("side", rng, direction=1.0)] + [_body_window("walk", rng, phase=i) for i in range(4)]
    acc = _in_phone(body, mount)
    modes, decided = _decide(acc, kinds, scope="recording")
    assert decided[0] and modes[0] == "side_right"
    modes, decided = _decide(acc, kinds, scope="before")  # no walking before it
    assert not decided.any() and modes[0] == "side_left"  # the model's answer stays
    modes, decided = _decide(acc, kinds, min_walk=5)
    assert not decided.any()


def test_bad_arguments():
    up = fw = lat = np.zeros((2, 3))
    with pytest.raises(InputError, match="scope"):
        body_frame_side_directions(["walk", "side_left"], [False, True], [True, False], up, fw, lat, scope="after")
    with pytest.raises(InputError, match="one modes / unsure / walking / vector row per window"):
        body_frame_side_directions(["walk"], [False, True], [True, False], up, fw, lat)
    with pytest.raises(InputError, match=r"shape \(n, 3\)"):
        window_vectors(np.zeros((10, 2)), [0], [5])


def test_score_recording_on_a_simulated_pocket_walker():
    """The study's scoring on one simulated walker (front pocket, all five modes): the rows add up and a side step the
    model reads in a pocket is unsure before; the body frame decides it where the recording has walking."""
    from experiments.scripts.side_direction import simulate
    from gaitml.models import load_model

    model = load_model(ROOT / "models" / "demo")
    rec = simulate(7, 1, ("front-pocket",))[0]
    rows = score_recording(model, rec)
    side = [r for r in rows if r["label"] in ("side_left", "side_right") and r["read_side"]]
    assert side and all(r["unsure_before"] for r in side)
    assert not any(r["unsure_after"] for r in side)  # this walker walks for more than 3 s
    t = direction_table(pd.DataFrame(rows))
    assert set(t["position"]) == {"front-pocket"} and (t["windows read as a side step"] > 0).all()
