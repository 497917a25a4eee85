"""experiments.scripts.lopo_span: the span selection rule and the cache key of each seed set."""

from __future__ import annotations

import pandas as pd

from experiments.scripts import lopo_domain as ld
from experiments.scripts import lopo_span as ls
from gaitml.simulate import POSITIONS


def _rows(span: int, flagged: list[float], false_alarm: float) -> list[dict]:
    return [
        {"left out": p, "span": span, "left-out flagged": f, "false alarms": false_alarm} for p, f in zip(POSITIONS, flagged, strict=True)
    ]


def test_the_rule_takes_the_most_positions_at_80_percent_within_the_false_alarm_limit_and_the_shorter_span_on_a_tie():
    df = pd.DataFrame(
        _rows(10, [0.0, 0.0, 0.2, 0.0, 0.6, 0.7, 1.0], 0.005)
        + _rows(20, [0.0, 0.0, 0.2, 0.0, 0.85, 0.7, 1.0], 0.005)
        + _rows(30, [0.0, 0.0, 0.2, 0.0, 0.85, 0.81, 1.0], 0.009)
        + _rows(40, [0.0, 0.0, 0.3, 0.0, 0.9, 0.9, 1.0], 0.006)  # as many as 30: the shorter span wins
        + _rows(60, [0.9, 0.0, 0.9, 0.0, 0.9, 0.9, 1.0], 0.011)  # most positions, but too many false alarms
        + [{"left out": "hand-held (flat + tilted)", "span": 10, "left-out flagged": 1.0, "false alarms": 0.0}]  # groups are not counted
    )
    chosen, summary = ls.choose(df)
    assert chosen == 30
    assert summary.loc[60, "reached"] == 5 and summary.loc[30, "reached"] == 3 and summary.loc[10, "reached"] == 1


def test_no_span_within_the_false_alarm_limit_keeps_the_current_one():
    df = pd.DataFrame(_rows(10, [1.0] * 7, 0.02) + _rows(40, [1.0] * 7, 0.03))
    assert ls.choose(df)[0] == ls.CURRENT_SPAN


def test_each_seed_set_has_its_own_cache_key():
    keys = {ld.cache_key(sets=sets) for sets in ls.SEED_SETS.values()}
    assert len(keys) == 2 and ld.cache_key(sets=ld.SETS) == ld.cache_key()
    assert ls.SEED_SETS["selection"] == ld.SETS  # the seeds every earlier choice was made on
