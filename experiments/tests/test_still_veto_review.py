"""Lab: the review script's table comparison (experiments/scripts/still_veto_review.py)."""

from __future__ import annotations

import pandas as pd
import pytest

from experiments.scripts.still_veto_review import differing


def test_differing_counts_rows_per_column_and_refuses_other_windows():
    a = pd.DataFrame({"still": [True, False, False], "mode": ["still", "walk", "walk"]})
    b = pd.DataFrame({"still": [True, True, False], "mode": ["still", "still", "run"]})
    assert differing(a, b, ("still", "mode")) == {"still": 1, "mode": 2}
    assert differing(a, a, ("still", "mode")) == {"still": 0, "mode": 0}
    with pytest.raises(ValueError, match="differ in length"):
        differing(a, b.iloc[:2], ("still",))
