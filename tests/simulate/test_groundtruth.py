"""Ground truth consistency: steps, trajectory, routes, conventions of DESIGN sec. 2."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.simulate import (
    MODE_OFFSET_RAD,
    arc_path,
    make_path,
    rectangle_path,
    sample_subjects,
    simulate_dataset,
    simulate_recording,
    simulate_route,
)

#: DESIGN sec. 2 / paper 003 eq. (10)-(11), physical reading: direction of travel per mode.
DESIGN_OFFSET = {"walk": 0.0, "run": 0.0, "backward": np.pi, "side_left": -np.pi / 2, "side_right": np.pi / 2}


def integrate_steps(steps):
    """Dead reckoning with the true steps: L (sin(theta + offset), cos(theta + offset))."""
    off = steps["mode"].map(DESIGN_OFFSET).to_numpy(dtype=float)
    a = steps["heading_rad"].to_numpy() + off
    L = steps["step_length_m"].to_numpy()
    return np.array([np.sum(L * np.sin(a)), np.sum(L * np.cos(a))])


def test_offsets_match_design():
    assert {k: float(v) for k, v in MODE_OFFSET_RAD.items()} == pytest.approx(DESIGN_OFFSET)


@pytest.mark.parametrize("route", ["rectangle", "arc"])
def test_integrated_steps_reach_the_true_end_on_routes(route):
    rec = simulate_route(route, seed=4)
    traj = rec.reference["trajectory"]
    end = traj[["x_m", "y_m"]].to_numpy()[-1]
    assert np.linalg.norm(integrate_steps(rec.reference["steps"]) - end) < 0.01


def test_integrated_steps_reach_the_true_end_in_datasets():
    for rec in simulate_dataset(4, 90.0, seed=8, pauses=True) + [simulate_route("random", seed=3, duration_s=90.0)]:
        traj = rec.reference["trajectory"]
        end = traj[["x_m", "y_m"]].to_numpy()[-1]
        assert np.linalg.norm(integrate_steps(rec.reference["steps"]) - end) < 0.01
        # positions after each step agree with the trajectory at the step events
        steps = rec.reference["steps"]
        idx = np.round(steps["t_s"].to_numpy() * rec.sampling_rate_hz).astype(int)
        ok = idx < rec.n_samples
        xy = traj[["x_m", "y_m"]].to_numpy()[idx[ok]]
        assert np.abs(xy - steps[["x_m", "y_m"]].to_numpy()[ok]).max() < 0.1  # within a sample's travel


def test_single_mode_geometry():
    """Walking backward or side-stepping moves the way DESIGN says relative to the facing heading."""
    subj = sample_subjects(1, seed=0)[0]
    for mode, off in DESIGN_OFFSET.items():
        rec = simulate_recording(subj, modes=(mode,), duration_s=12.0, seed=1)
        steps = rec.reference["steps"]
        # first leg of the straight route: facing constant, travel along theta + offset
        first = steps.iloc[:5]
        d = first[["x_m", "y_m"]].to_numpy()[-1] - np.array([0.0, 0.0])
        theta = first["heading_rad"].iloc[0]
        want = np.array([np.sin(theta + off), np.cos(theta + off)])
        assert np.dot(d / np.linalg.norm(d), want) > 0.99, mode


def test_trajectory_is_continuous_and_speed_plausible():
    rec = simulate_dataset(1, 120.0, seed=2)[0]
    traj = rec.reference["trajectory"]
    v = np.hypot(np.diff(traj["x_m"]), np.diff(traj["y_m"])) * rec.sampling_rate_hz
    assert v.max() < 6.0  # m/s: no jumps
    steps = rec.reference["steps"]
    assert abs(steps["step_length_m"].sum() - np.sum(v) / rec.sampling_rate_hz) < 0.01 * steps["step_length_m"].sum() + 0.05


def test_route_paths():
    r = rectangle_path()
    assert r.total_length_m == pytest.approx(262.0)
    pts = r.points(0.1)
    assert np.linalg.norm(pts[-1]) < 1e-6  # closed
    span = pts.max(axis=0) - pts.min(axis=0)
    assert sorted(span) == pytest.approx([50.0, 81.0], abs=1.0)
    a = arc_path()
    assert a.total_length_m == pytest.approx(400.0)
    assert np.linalg.norm(a.points(0.1)[-1]) < 1e-6
    assert a.heading_at(150.0) == pytest.approx(np.pi / 2)  # half way round the first bend
    rng = np.random.default_rng(0)
    for name in ("straight", "random"):
        p = make_path(name, rng, min_length_m=300.0)
        assert p.total_length_m >= 300.0
        assert np.any(p.curvature_radpm != 0)
