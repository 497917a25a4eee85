"""IntervalLabeller, rule 'change' (the default): a boundary moves only to evidence of the mode change itself."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.labels import SNAP_DETECTORS, IntervalLabeller, evaluate_snapping
from gaitml.recording import Recording

FS = 50.0


def _gait(step_s: float, amp: float, seconds: float, rng: np.random.Generator) -> np.ndarray:
    """|acc| of steps of ``step_s`` with an impact of height ``amp`` at the end of each step (single-peak finds it)."""
    n_steps = int(round(seconds / step_s))
    out = []
    for _ in range(n_steps):
        n = int(round(step_s * FS))
        u = np.arange(n) / n
        bump = amp * np.exp(-0.5 * ((u - 0.9) * step_s / 0.04) ** 2) - 0.3 * amp * np.sin(np.pi * u) ** 2
        out.append(bump + rng.normal(0, 0.05 * amp, n))
    return np.concatenate(out)


def _walk_then(step_b: float, amp_b: float) -> tuple[Recording, float]:
    """20 s of walking (0.5 s steps, impacts of 4 m/s^2) then 20 s of another gait; returns it and the true change (s)."""
    rng = np.random.default_rng(7)
    a = _gait(0.5, 4.0, 20.0, rng)
    b = _gait(step_b, amp_b, 20.0, rng)
    z = 9.81 + np.concatenate([a, b])
    acc = np.column_stack([0.1 * (z - 9.81), 0.2 * (z - 9.81), z])
    return Recording.from_arrays(acc, FS), len(a) / FS


def _boundary(rec: Recording, t_change: float, written: float, **kw) -> pd.Series:
    iv = pd.DataFrame({"start_s": [0.0, written], "end_s": [written, rec.duration_s], "label": ["walk", "run"]})
    b = IntervalLabeller(snap="steps", detector="single-peak", **kw).label(rec, iv).boundaries_
    return b[b["t_s"].sub(written).abs() < 1e-9].iloc[0]


@pytest.mark.parametrize("offset", [-0.3, -0.17, 0.22, 0.35])
def test_a_clear_change_of_gait_is_found_from_either_side(offset):
    rec, t0 = _walk_then(0.33, 10.0)  # walk -> run: shorter, harder steps
    row = _boundary(rec, t0, t0 + offset)
    assert row["status"] == "snapped"
    # the step event is the impact, a few samples before the end of the synthetic step
    assert abs(row["snapped_t_s"] - t0) <= 0.1
    assert abs(row["snapped_t_s"] - t0) < abs(offset)


def test_no_change_of_gait_leaves_the_boundary_as_written():
    rec, t0 = _walk_then(0.5, 4.0)  # the same gait on both sides: nothing marks the change
    row = _boundary(rec, t0, t0 + 0.2)
    assert row["status"] == "ambiguous" and row["shift_s"] == 0.0
    nearest = _boundary(rec, t0, t0 + 0.2, rule="nearest")
    assert nearest["status"] == "snapped"  # the nearest rule moves it regardless


def test_a_move_within_the_detector_timing_is_not_made():
    rec, t0 = _walk_then(0.33, 10.0)
    found = _boundary(rec, t0, t0 + 0.3)["snapped_t_s"]
    row = _boundary(rec, t0, found + 0.04)
    assert row["status"] == "within timing" and row["shift_s"] == 0.0


def test_bad_rule():
    rec, _ = _walk_then(0.33, 10.0)
    iv = pd.DataFrame({"start_s": [0.0], "end_s": [5.0], "label": ["walk"]})
    with pytest.raises(Exception, match="rule"):
        IntervalLabeller(rule="closest").label(rec, iv)


@pytest.mark.parametrize("stated", [None, 0.3])
def test_snapping_is_never_worse_than_as_written_on_any_seed(stated):
    """Mixed-mode simulated walks (+-0.3 s boundary noise): for every detector, no seed loses agreement, and the
    snapping helps on the whole (at least one boundary in ten moved, the mean agreement up)."""
    df = evaluate_snapping(range(200, 205), noise_s=0.3, duration_s=90.0, snap_noise_s=stated)
    p = df.pivot(index="seed", columns="method", values="agreement")
    for det in SNAP_DETECTORS:
        assert (p[det] >= p["none"]).all(), (det, (p[det] - p["none"]).min())
    gain = p.drop(columns="none").mean().sub(p["none"].mean())
    assert (gain >= 0).all() and gain.max() > 0.0005
    assert df[df["method"] != "none"]["snapped_share"].mean() >= 0.05
