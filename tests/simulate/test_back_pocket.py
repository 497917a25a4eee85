"""The back pocket's pelvis share and in-pocket roll (gaitml.simulate.positions): draws, range checks, physics, manifest."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate import Placement, sample_subjects, simulate_recording
from gaitml.simulate.positions import (
    BACK_POCKET_RANGE,
    _segment_angles,
    _smooth_weights,
)


def _walk(p: Placement, seed: int = 4, duration_s: float = 40.0):
    subj = sample_subjects(1, seed)[0]
    return simulate_recording(subj, route="straight", duration_s=duration_s, modes=("walk",), seed=seed, placement=p)


@pytest.mark.parametrize("bad", [-0.1, 1.5])
def test_pelvis_share_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="pelvis_share"):
        Placement("back-pocket", pelvis_share=bad)


def test_the_blend_takes_the_thigh_at_share_0_and_the_pelvis_at_share_1():
    """Share 0: the thigh's rotation only (the pelvis's amplitudes do not matter); share 1: the pelvis's
    only (the thigh's do not matter); in between, the weighted sum of the two."""
    fs, n = 50.0, 500
    phi = np.arange(n) / fs * 1.9
    w = _smooth_weights(np.zeros(n, dtype=int), np.ones(n), fs)  # mode 0 = walk
    base = Placement.random("back-pocket", np.random.default_rng(2))

    def angles(**kw):
        return np.array(_segment_angles(dataclasses.replace(base, **kw), phi, w))

    thigh = angles(pelvis_share=0.0)
    assert np.array_equal(thigh, angles(pelvis_share=0.0, pelvis_yaw_deg=1.0, pelvis_roll_deg=9.0, pelvis_pitch_deg=0.5))
    pelvis = angles(pelvis_share=1.0)
    assert np.array_equal(pelvis, angles(pelvis_share=1.0, thigh_flex_amp_deg=30.0, thigh_rotation_deg=1.0))
    assert np.allclose(angles(pelvis_share=0.3), 0.7 * thigh + 0.3 * pelvis, atol=1e-12)
    belt = dataclasses.replace(Placement.random("belt", np.random.default_rng(2)), **{
        k: getattr(base, k) for k in ("pelvis_yaw_deg", "pelvis_roll_deg", "pelvis_pitch_deg")
    })  # fmt: skip
    assert np.allclose(pelvis, np.array(_segment_angles(belt, phi, w)), atol=1e-12)  # the belt's pelvis


def test_the_pocket_roll_turns_the_phone_in_the_screen_plane():
    p = dataclasses.replace(Placement.random("back-pocket", np.random.default_rng(3)), tilt_y_deg=0.0, tilt_z_deg=5.0, pocket_roll_deg=12.0)
    same = dataclasses.replace(p, tilt_z_deg=17.0, pocket_roll_deg=0.0)
    assert np.allclose(p.mount(), same.mount(), atol=1e-12)
    up = p.mount().T @ np.array([0.0, 0.0, 1.0])
    assert np.degrees(np.arctan2(abs(up[0]), abs(up[1]))) == pytest.approx(17.0, abs=1e-6)


def test_manifest_carries_the_pelvis_share_and_roll(tmp_path):
    import pandas as pd

    from gaitml.simulate import simulate_dataset, write_simulation

    write_simulation(simulate_dataset(2, 10.0, ("walk",), seed=3, positions=("back-pocket", "belt")), tmp_path / "sim")
    man = pd.read_csv(tmp_path / "sim" / "manifest.csv")
    back = man[man["position"] == "back-pocket"]
    lo, hi = BACK_POCKET_RANGE["pelvis_share"]
    assert np.all((back["carry_pelvis_share"] >= lo) & (back["carry_pelvis_share"] <= hi))
    assert np.all(np.abs(back["carry_pocket_roll_deg"]) <= BACK_POCKET_RANGE["pocket_roll_deg"][1])
    assert np.all(man[man["position"] == "belt"]["carry_pelvis_share"] == 0.0)
