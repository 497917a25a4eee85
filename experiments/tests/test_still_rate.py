"""Lab: the still-rate study's rate-agreement table (experiments/scripts/still_rate.py)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.still_rate import rate_agreement


def _preds(n: int, factor: float) -> pd.DataFrame:
    t = np.arange(n) * 0.75
    lab = np.where(np.arange(n) % 4 == 0, "still", "walk")
    base = np.where(lab == "still", 0.2, 1.0)
    return pd.DataFrame(
        {
            "t_start_s": t,
            "label": lab,
            "label_fraction": 1.0,
            "stat_std": base * factor,
            "stat_range": base * factor**2,
            "stat_std_lp": base,
        }
    )


def test_the_ratio_of_each_statistic_is_read_per_motion_and_window_kind():
    items = [{"motion": "Texting", "mode": "walk", "subject": "A"}]
    t = rate_agreement(items, [_preds(120, 1.0)], [_preds(120, 0.8)])
    row = t[(t["windows"] == "moving") & (t["motion"] == "all")].iloc[0]
    assert row["n"] == 90
    assert row["std: 20 Hz / 50 Hz (p10-p90)"].startswith("0.800")
    assert row["range: 20 Hz / 50 Hz (p10-p90)"].startswith("0.640")
    assert row["std_lp: 20 Hz / 50 Hz (p10-p90)"].startswith("1.000")
    assert set(t["windows"]) == {"moving", "standing"}


def test_windows_that_do_not_line_up_are_refused():
    import pytest

    items = [{"motion": "Texting", "mode": "walk", "subject": "A"}]
    shifted = _preds(120, 1.0)
    shifted["t_start_s"] += 0.5
    with pytest.raises(RuntimeError, match="do not line up"):
        rate_agreement(items, [_preds(120, 1.0)], [shifted])
