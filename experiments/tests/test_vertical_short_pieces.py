"""experiments.scripts.vertical_short_pieces: which bouts each candidate rule removes, and the rates and losses it scores."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.vertical_short_pieces import kept_rate, losses, removed


def _bouts() -> pd.DataFrame:
    # a swinging-hand bout (symmetry broken, strong clean stride rotation), a stroke-like gesture bout (symmetry
    # broken, stride rotation 2 x step), a symmetric walk bout, a long bout (exempt), a bout the rotation test rejects
    return pd.DataFrame(
        {
            "n_steps": [10, 6, 12, 40, 5],
            "rotation_step_rad_s": [0.3, 0.8, 0.2, 0.3, 3.0],
            "rotation_stride_rad_s": [1.4, 1.6, 0.5, 1.4, 0.2],
            "stride_vertical_fraction": [0.6, 0.6, 0.05, np.nan, 0.9],
            "reason": ["", "", "", "", "rotation"],
        }
    )


def test_each_family_removes_the_bouts_it_should():
    b = _bouts()
    assert removed(b, ("thr", np.inf, np.nan)).tolist() == [False] * 5
    assert removed(b, ("thr", 0.4, np.nan)).tolist() == [True, True, False, False, False]
    assert removed(b, ("thr", 0.7, np.nan)).tolist() == [False] * 5
    # skip the test where the stride rotation is at arm-swing level (>= 1.5 rad/s): the 1.4 swing is still removed
    assert removed(b, ("swing", 0.4, 1.5)).tolist() == [True, False, False, False, False]
    assert removed(b, ("swing", 0.4, 1.0)).tolist() == [False] * 5
    # skip it where the stride rotation is at least 3 x the step rotation: the swing (4.7 x) is kept, the gesture (2 x) not
    assert removed(b, ("ratio", 0.4, 3.0)).tolist() == [False, True, False, False, False]


def test_rates_and_losses_count_steps():
    b = _bouts()
    sim = pd.concat([b.assign(kind="gestures", seed=0), b.assign(kind="desk", seed=0)], ignore_index=True)
    # 120 s recordings: steps per minute = kept steps / 2
    assert kept_rate(sim, [0], ("thr", np.inf, np.nan), "gestures") == (10 + 6 + 12 + 40) / 2.0
    assert kept_rate(sim, [0], ("thr", 0.4, np.nan), "gestures") == (12 + 40) / 2.0
    ty = b.assign(person="A", motion="Swinging")
    lo = losses(ty, ("thr", 0.4, np.nan), ["A"])
    r = lo.loc[("A", "Swinging")]
    assert (r["steps"], r["rot"], r["lost"]) == (73, 5, 16)
    assert abs(r["share"] - 16 / 73) < 1e-12
