"""Non-gait phone motion (issue 30): no steps in the truth, gravity and gyroscope consistent, reproducible."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.simulate.nongait import simulate_nongait


@pytest.mark.parametrize("kind", ["gestures", "desk"])
def test_nongait_recording(kind):
    rec = simulate_nongait(kind, duration_s=60, seed=2)
    assert rec.reference["n_steps_true"] == 0 and len(rec.reference["steps"]) == 0
    a = np.linalg.norm(rec.acc, axis=1)
    assert abs(np.median(a) - 9.81) < 0.5  # gravity dominates
    assert a.std() > 0.1  # but the phone moves
    again = simulate_nongait(kind, duration_s=60, seed=2)
    assert np.array_equal(rec.acc, again.acc)
    assert not np.array_equal(rec.acc, simulate_nongait(kind, duration_s=60, seed=3).acc)


def test_desk_phone_lies_still_part_of_the_time():
    rec = simulate_nongait("desk", duration_s=120, seed=1)
    g = np.linalg.norm(rec.gyr, axis=1)
    assert np.mean(g < 0.02) > 0.2


def test_bad_kind_and_duration():
    with pytest.raises(InputError, match="gestures, desk"):
        simulate_nongait("dance")
    with pytest.raises(InputError, match="duration_s"):
        simulate_nongait("desk", duration_s=1.0)
