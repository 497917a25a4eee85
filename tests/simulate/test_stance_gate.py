"""The back pocket's one-sided step (``stance_gate``, gaitml.simulate.positions): range checks and the gate's physics."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate import Placement, sample_subjects, simulate_recording
from gaitml.simulate.positions import STANCE_GATE_EDGE, stance_gate


def _walk(p: Placement, seed: int = 4, duration_s: float = 40.0):
    subj = sample_subjects(1, seed)[0]
    return simulate_recording(subj, route="straight", duration_s=duration_s, modes=("walk",), seed=seed, placement=p)


@pytest.mark.parametrize("bad", [-0.1, 1.5])
def test_a_gate_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="stance_gate"):
        Placement("back-pocket", stance_gate=bad)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_the_gate_passes_the_carrying_legs_step_and_damps_the_others(side):
    """1 through the carrying leg's step (heel strike of that leg to the other's), 1 - gate through the
    other's, turning within a few tenths of a step around each strike; 0 gives exactly 1."""
    phi = np.linspace(0.0, 8.0, 8001)
    g = stance_gate(phi, side, 0.7)
    own0 = 1.0 if side > 0 else 0.0  # right heel strikes at odd phi, left at even
    x = np.mod(phi - own0, 2.0)
    inner = 3 * STANCE_GATE_EDGE
    assert np.allclose(g[(x > inner) & (x < 1 - inner)], 1.0, atol=0.02)
    assert np.allclose(g[(x > 1 + inner) & (x < 2 - inner)], 0.3, atol=0.02)
    assert g.min() >= 0.3 - 1e-12 and g.max() <= 1.0 + 1e-12
    assert np.array_equal(stance_gate(phi, side, 0.0), np.ones_like(phi))
