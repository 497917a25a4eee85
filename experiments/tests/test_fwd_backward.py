"""experiments.scripts.fwd_backward: the comparison tables and the adoption rule's verdict on known inputs."""

from __future__ import annotations

import pandas as pd

from experiments.scripts.fwd_backward import compare_sim, compare_tyrex, verdict


def _sim(right: dict) -> pd.DataFrame:
    return pd.DataFrame(
        [{"position": p, "mode": m, "n": 100, "right": r, "flagged": 0, "wrong": 100 - r, "side": 0} for (p, m), r in right.items()]
    )


def test_the_rule_holds_only_when_all_three_parts_hold():
    base = _sim({("hand-flat", "backward"): 30, ("hand-tilted", "backward"): 60, ("front-pocket", "walk"): 90})
    good = _sim({("hand-flat", "backward"): 91, ("hand-tilted", "backward"): 95, ("front-pocket", "walk"): 89})
    tyrex_b = pd.DataFrame([{"motion": "Texting", "left_out": p, "n": 100, "right": 98, "wrong": 2} for p in ("A", "B")])
    tyrex_same = tyrex_b.copy()
    ok = verdict(compare_sim(base, good), compare_tyrex(tyrex_b, tyrex_same)[0])
    assert [h for _, h, _ in ok] == [True, True, True]
    # a hand-held backward row under 0.90; another row down by 0.03; tyrex silently wrong up by 0.01
    low = _sim({("hand-flat", "backward"): 89, ("hand-tilted", "backward"): 95, ("front-pocket", "walk"): 87})
    worse = tyrex_b.assign(right=97, wrong=3)
    bad = verdict(compare_sim(base, low), compare_tyrex(tyrex_b, worse)[0])
    assert [h for _, h, _ in bad] == [False, False, False]
    assert "front-pocket walk 0.900 -> 0.870" in bad[1][2] and "Texting" in bad[2][2]


def test_tyrex_comparison_pools_over_the_left_out_people():
    b = pd.DataFrame(
        [{"motion": "Swinging", "left_out": p, "n": n, "right": r, "wrong": n - r} for p, n, r in (("A", 100, 90), ("B", 300, 300))]
    )
    c = b.assign(right=[100, 297], wrong=[0, 3])
    pooled, per = compare_tyrex(b, c)
    row = pooled.iloc[0]
    assert row["right_base"] == 390 / 400 and row["right_cand"] == 397 / 400 and abs(row["wrong_change"] - (3 - 10) / 400) < 1e-12
    assert len(per) == 2
