"""Geometry of the position updates (paper 003 eqs. 10-11, DESIGN sec. 4 physical reading)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gaitml.errors import InputError
from gaitml.evaluation.trajectory import closure_error
from gaitml.pdr.update import forward_update, mode_offsets_rad, multi_state_update

angles = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(theta=angles, n=st.integers(1, 40), length=st.floats(0.1, 2.0))
def test_n_forward_then_n_backward_returns_to_start(theta, n, length):
    modes = ["walk"] * n + ["backward"] * n
    xy = multi_state_update(np.full(2 * n, length), np.full(2 * n, theta), modes, start_xy_m=(3.0, -2.0))
    assert np.allclose(xy[-1], (3.0, -2.0), atol=1e-9)
    # and the forward leg went along the heading
    assert np.allclose(xy[n] - xy[0], n * length * np.array([np.sin(theta), np.cos(theta)]), atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(theta=angles, length=st.floats(0.1, 2.0))
def test_side_steps_move_to_the_persons_left_and_right(theta, length):
    facing = np.array([np.sin(theta), np.cos(theta)])
    for mode, sign in (("side_left", 1.0), ("side_right", -1.0)):
        d = multi_state_update([length], [theta], [mode])[1]
        cross = facing[0] * d[1] - facing[1] * d[0]  # > 0: d is counter-clockwise of facing = to the left
        assert sign * cross == pytest.approx(length, rel=1e-9)
        assert abs(facing @ d) < 1e-9


def test_left_step_when_facing_north_goes_west_and_right_goes_east():
    assert np.allclose(multi_state_update([1.0], [0.0], ["side_left"])[1], (-1.0, 0.0), atol=1e-12)
    assert np.allclose(multi_state_update([1.0], [0.0], ["side_right"])[1], (1.0, 0.0), atol=1e-12)
    assert np.allclose(multi_state_update([1.0], [np.pi / 2], ["walk"])[1], (1.0, 0.0), atol=1e-12)  # east


@pytest.mark.parametrize("theta0", [0.0, 0.3, -2.0, np.pi])
@pytest.mark.parametrize("clockwise", [True, False])
def test_four_right_angle_legs_close_a_square(theta0, clockwise):
    n = 25
    turn = np.pi / 2 if clockwise else -np.pi / 2
    heading = np.concatenate([np.full(n, theta0 + k * turn) for k in range(4)])
    xy = forward_update(np.full(4 * n, 0.7), heading)
    assert np.allclose(xy[-1], 0.0, atol=1e-9)
    # corners are a square of side n * 0.7
    corners = xy[[0, n, 2 * n, 3 * n]]
    sides = np.linalg.norm(np.diff(np.vstack([corners, corners[:1]]), axis=0), axis=1)
    assert np.allclose(sides, n * 0.7)


def test_square_walked_with_all_modes_while_facing_north_closes():
    # forward north, right-step east, backward south, left-step west: the facing never changes
    n = 10
    modes = ["walk"] * n + ["side_right"] * n + ["backward"] * n + ["side_left"] * n
    xy = multi_state_update(np.full(4 * n, 0.5), np.zeros(4 * n), modes)
    assert np.allclose(xy[-1], 0.0, atol=1e-9)
    assert np.allclose(xy[2 * n], (5.0, 5.0))


def test_forward_only_update_cannot_close_that_square():
    n = 10
    xy = forward_update(np.full(4 * n, 0.5), np.zeros(4 * n))
    assert np.allclose(xy[-1], (0.0, 20.0))


@settings(max_examples=40, deadline=None)
@given(scale=st.floats(0.2, 5.0), seed=st.integers(0, 1000))
def test_closure_error_percent_is_invariant_to_a_uniform_step_length_scale(scale, seed):
    rng = np.random.default_rng(seed)
    n = 60
    L = rng.uniform(0.4, 0.9, n)
    theta = np.repeat([0.0, np.pi / 2, np.pi, 1.5 * np.pi], n // 4) + rng.normal(0, 0.05, n)
    modes = rng.choice(["walk", "run", "backward", "side_left", "side_right"], n)
    e1, p1 = closure_error(multi_state_update(L, theta, modes))
    e2, p2 = closure_error(multi_state_update(scale * L, theta, modes))
    assert p2 == pytest.approx(p1, rel=1e-9, abs=1e-12)
    assert e2 == pytest.approx(scale * e1, rel=1e-9, abs=1e-12)


def test_mode_offsets_and_unknown_modes():
    assert np.allclose(mode_offsets_rad(["walk", "run", "backward", "side_left", "side_right"]), [0, 0, np.pi, -np.pi / 2, np.pi / 2])
    with pytest.raises(InputError, match="unknown motion mode"):
        mode_offsets_rad(["walk", "stairs"])
    assert np.allclose(mode_offsets_rad(["stairs"], unknown="forward"), [0.0])


@pytest.mark.parametrize(
    ("L", "th", "match"),
    [([1.0, 2.0], [0.0], "same length"), ([np.nan], [0.0], "finite"), ([-1.0], [0.0], ">= 0")],
)
def test_bad_inputs(L, th, match):
    with pytest.raises(InputError, match=match):
        forward_update(L, th)


def test_modes_length_must_match():
    with pytest.raises(InputError, match="one entry per step"):
        multi_state_update([1.0, 1.0], [0.0, 0.0], ["walk"])
