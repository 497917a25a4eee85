"""experiments/scripts/tyrex_gyrocal.py: the adoption rule counts as written, and the plain gyroscope heading given a
bias removes exactly that bias (synthetic, no shared data)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_gyrocal import RULE_MOTIONS, adoption, heading_about_gravity
from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording


def _table(held: dict, tracked: dict, n: int = 4) -> pd.DataFrame:
    rows = []
    for m in RULE_MOTIONS:
        for k in range(n):
            rows.append({"file": f"{m}{k}", "motion": m, "variant": "still log, held", "drift_deg_per_min": held[m] + k})
            rows.append({"file": f"{m}{k}", "motion": m, "variant": "still log, tracked", "drift_deg_per_min": -(tracked[m] + k)})
    return pd.DataFrame(rows)


def test_tracked_is_adopted_only_when_lower_in_five_motions_and_more_recordings():
    base = dict.fromkeys(RULE_MOTIONS, 10.0)
    better5 = {m: (9.0 if i < 5 else 11.0) for i, m in enumerate(RULE_MOTIONS)}
    r = adoption(_table(base, better5))
    assert r["adopt_tracked"] and len(r["tracked_lower_median_in"]) == 5  # the sign of the drift does not count
    better4 = {m: (9.0 if i < 4 else 11.0) for i, m in enumerate(RULE_MOTIONS)}
    assert not adoption(_table(base, better4))["adopt_tracked"]
    # lower medians in 5 motions but higher in more recordings: not adopted
    t = _table(base, better5, n=3)
    worse = t[(t["variant"] == "still log, tracked") & t["motion"].isin(RULE_MOTIONS[5:])].index
    t.loc[worse, "drift_deg_per_min"] = -100.0
    extra = pd.DataFrame(
        [
            {"file": f"x{k}", "motion": RULE_MOTIONS[6], "variant": v, "drift_deg_per_min": d}
            for k in range(20)
            for v, d in (("still log, held", 1.0), ("still log, tracked", 2.0))
        ]
    )
    r = adoption(pd.concat([t, extra], ignore_index=True))
    assert r["paired_higher"] > r["paired_lower"] and not r["adopt_tracked"]


def test_the_plain_heading_given_a_bias_removes_it():
    fs, n = 100.0, 6000
    acc = np.tile([0.0, 0.0, GRAVITY_MS2], (n, 1))
    bias = np.array([0.01, 0.02, 0.05])
    rec = Recording.from_arrays(acc, fs, gyr=np.tile(bias, (n, 1)))
    raw = heading_about_gravity(rec)
    np.testing.assert_allclose(raw[-1], -0.05 * (n - 1) / fs, rtol=1e-6)  # about up (z): compass heading decreases
    np.testing.assert_allclose(heading_about_gravity(rec, bias), 0.0, atol=1e-9)
