"""The foot-mounted IMU simulator (issue 30): still in foot flat, literature stance durations, reproducible."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.simulate.foot import RUN_CONTACT_TIME_RANGE_S, simulate_foot


@pytest.mark.parametrize("mode", ["walk", "run"])
def test_foot_is_still_in_foot_flat_and_moves_in_swing(mode):
    rec = simulate_foot(modes=(mode,), duration_s=30, seed=1)
    flat = rec.reference["zupt_mask"]
    g = np.linalg.norm(rec.gyr, axis=1)
    a = np.linalg.norm(rec.acc, axis=1)
    assert np.percentile(g[flat], 99) < np.radians(3.0)  # sensor noise and bias only
    assert abs(np.median(a[flat]) - GRAVITY_MS2) < 0.2
    assert np.percentile(np.degrees(g[~flat]), 90) > (300 if mode == "walk" else 400)


def test_running_contact_times_are_in_the_literature_range():
    st = simulate_foot(modes=("run",), duration_s=60, seed=2).reference["stances"]
    stride = np.diff(st["t_heel_strike_s"].to_numpy())
    assert RUN_CONTACT_TIME_RANGE_S[0] - 0.03 <= st["contact_s"].min() and st["contact_s"].max() <= RUN_CONTACT_TIME_RANGE_S[1]
    assert 0.18 <= st["contact_s"].median() <= 0.30  # 0.2-0.3 s at 2.5-4 m/s (Novacheck 1998)
    assert 0.55 <= np.median(stride) <= 0.85  # running cadence 2.5-3.1 steps/s
    flat = st["t_heel_off_s"] - st["t_flat_start_s"]
    assert (flat > 0).all() and flat.median() < 0.2


def test_walking_stance_is_sixty_percent_of_the_stride():
    st = simulate_foot(modes=("walk",), duration_s=60, seed=3).reference["stances"]
    stride = np.diff(st["t_heel_strike_s"].to_numpy())
    duty = (st["t_toe_off_s"] - st["t_heel_strike_s"]).to_numpy()[:-1] / stride
    assert 0.55 <= np.median(duty) <= 0.66


def test_same_seed_same_signal_and_bad_modes_rejected():
    a = simulate_foot(modes=("run", "walk"), duration_s=20, seed=5, segment_s=(5.0, 8.0))
    b = simulate_foot(modes=("run", "walk"), duration_s=20, seed=5, segment_s=(5.0, 8.0))
    assert np.array_equal(a.acc, b.acc) and np.array_equal(a.gyr, b.gyr)
    assert {"walk", "run"} <= set(np.unique(a.labels))
    with pytest.raises(InputError, match="walk, run only"):
        simulate_foot(modes=("side_left",), duration_s=10)
    with pytest.raises(InputError, match="side"):
        simulate_foot(side="middle", duration_s=10)
