"""The vigour of a carried phone (gaitml.simulate.positions): what it scales, what it leaves alone, its draw."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate import Placement, sample_subjects, simulate_recording
from gaitml.simulate.positions import VIGOUR_RANGE


def _walk(position: str, vigour: float, modes=("walk",), seed: int = 4, duration_s: float = 30.0):
    """The same subject, placement and seed at another vigour."""
    subj = sample_subjects(1, seed)[0]
    p = dataclasses.replace(Placement.random(position, np.random.default_rng(seed)), vigour=vigour)
    return simulate_recording(subj, route="straight", duration_s=duration_s, modes=modes, seed=seed, placement=p)


@pytest.mark.parametrize("position", ["front-pocket", "back-pocket", "bag"])
def test_vigour_scales_the_walking_intensity_but_not_the_steps(position):
    calm, base, vigorous = (_walk(position, v) for v in (0.7, 1.0, 1.6))
    sd = [np.std(np.linalg.norm(r.acc, axis=1)) for r in (calm, base, vigorous)]
    assert sd[0] < sd[1] < sd[2]
    assert sd[2] > 1.2 * sd[1]
    for r in (calm, vigorous):  # the same walk: steps and truth
        assert np.array_equal(r.reference["steps_t_s"], base.reference["steps_t_s"])
        assert np.array_equal(r.reference["trajectory"].to_numpy(), base.reference["trajectory"].to_numpy())
        # a pocket turns with the thigh whatever the vigour; a bag tilts with its own acceleration
        same_attitude = np.array_equal(r.reference["attitude_wxyz"], base.reference["attitude_wxyz"])
        assert same_attitude == (position != "bag")


def test_running_ignores_the_vigour():
    a, b = (_walk("front-pocket", v, modes=("run",), duration_s=20.0) for v in (1.0, 1.6))
    assert np.array_equal(a.acc, b.acc) and np.array_equal(a.gyr, b.gyr)


def test_the_vigour_is_drawn_after_every_other_field():
    """Seed 7's placements as drawn before the vigour existed (gaitml at 73c1965; the first and the
    last fields drawn are pinned): drawing the vigour first would change them."""
    p = Placement.random("front-pocket", np.random.default_rng(7))
    assert (p.side, p.upright, round(p.thigh_flex_amp_deg, 6), round(p.impact_gain, 6), round(p.wander_deg, 6)) == (
        -1.0,
        False,
        20.569827,
        1.15487,
        2.97792,
    )
    p = Placement.random("back-pocket", np.random.default_rng(7))
    assert (p.side, p.upright, round(p.tilt_x_deg, 6), round(p.wander_deg, 6)) == (-1.0, False, 18.378108, 2.97792)


@pytest.mark.parametrize("upright", [True, False])
@pytest.mark.parametrize("screen_out", [True, False])
def test_back_pocket_gravity_on_z_follows_the_screen_not_the_phone_top(upright, screen_out):
    """The buttock's surface faces backward and down: standing still, a screen facing out reads
    gravity negative on the phone's z axis, a screen facing the body positive, whichever way up."""
    p = dataclasses.replace(
        Placement.random("back-pocket", np.random.default_rng(3)),
        upright=upright,
        screen_out=screen_out,
        tilt_y_deg=0.0,
        tilt_z_deg=0.0,
        pocket_roll_deg=0.0,
    )
    m = p.mount()
    assert np.allclose(m.T @ m, np.eye(3), atol=1e-12) and np.isclose(np.linalg.det(m), 1.0)
    g_phone = m.T @ np.array([0.0, 0.0, 1.0])  # what the phone's axes read of "up" (gravity's reaction, in g)
    a = np.radians(p.tilt_x_deg)
    assert g_phone[2] == pytest.approx(-np.sin(a) if screen_out else np.sin(a))
    assert g_phone[1] == pytest.approx(np.cos(a) if upright else -np.cos(a))


@pytest.mark.parametrize("bad", [0.0, 0.1, 5.0])
def test_vigour_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="vigour"):
        Placement("front-pocket", vigour=bad)


def test_manifest_carries_the_vigour(tmp_path):
    from gaitml.simulate import simulate_dataset, write_simulation

    recs = simulate_dataset(2, 10.0, ("walk",), seed=3, positions=("front-pocket", "belt"))
    write_simulation(recs, tmp_path / "sim")
    import pandas as pd

    man = pd.read_csv(tmp_path / "sim" / "manifest.csv")
    assert "carry_vigour" in man.columns
    belt = man[man["position"] == "belt"]["carry_vigour"]
    assert np.all(belt == 1.0)
    lo, hi = VIGOUR_RANGE["front-pocket"]
    pocket = man[man["position"] == "front-pocket"]["carry_vigour"]
    assert np.all((pocket >= lo) & (pocket <= hi))
