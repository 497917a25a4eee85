"""The equality check of experiments/scripts/predict_speed.py finds a difference of one unit in the last place."""

from __future__ import annotations

import numpy as np
import pandas as pd

from experiments.scripts.predict_speed import same_bits


def test_one_ulp_apart_is_not_identical_and_nan_equals_nan():
    a = pd.DataFrame({"x": [1.0, np.nan, 3.0], "m": np.array(["walk", None, "run"], dtype=object)})
    b = a.copy()
    assert same_bits(a, b) == (True, 0.0)
    b.loc[2, "x"] = np.nextafter(3.0, 4.0)
    ok, diff = same_bits(a, b)
    assert not ok and 0 < diff < 1e-15
    assert not same_bits(a, a.astype({"x": np.float32}))[0]  # another dtype
    c = a.copy()
    c.loc[0, "m"] = "still"
    assert not same_bits({"t": a}, {"t": c})[0]
