"""Windowing: lengths/hops, majority labels, dropping and counting weak windows."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gaitml.errors import InputError
from gaitml.features import make_windows
from gaitml.recording import Recording


def _rec(n: int, labels=None, fs: float = 50.0) -> Recording:
    acc = np.tile([0.0, 0.0, 9.8], (n, 1))
    return Recording.from_arrays(acc, fs, labels=labels)


def test_window_grid_without_labels():
    w = make_windows(_rec(300))
    assert list(w.columns) == ["start", "end", "t_start_s", "t_end_s"]
    assert w.attrs["length_samples"] == 75 and w.attrs["hop_samples"] == 38
    np.testing.assert_array_equal(w["start"], np.arange(0, 300 - 75 + 1, 38))
    np.testing.assert_array_equal(w["end"] - w["start"], 75)
    np.testing.assert_allclose(w["t_end_s"], w["end"] / 50.0)
    assert w.attrs["n_total"] == len(w) and w.attrs["n_dropped"] == 0


def test_majority_label_fraction_and_dropping():
    # 100 walk, 10 run, 90 walk; windows of 20 samples, no overlap
    labels = np.array(["walk"] * 100 + ["run"] * 10 + ["walk"] * 30 + ["side_left"] * 12 + ["run"] * 8 + ["walk"] * 40)
    rec = _rec(len(labels), labels)
    w = make_windows(rec, 0.4, 0.0, min_label_fraction=0.0)
    assert len(w) == 10
    row = w.iloc[5]  # samples 100..120: 10 run, 10 walk -> tie goes to the label sorting first ('run')
    assert row["label"] == "run" and row["label_fraction"] == pytest.approx(0.5)
    row = w.iloc[7]  # samples 140..160: 12 side_left + 8 run
    assert row["label"] == "side_left" and row["label_fraction"] == pytest.approx(0.6)
    strict = make_windows(rec, 0.4, 0.0, min_label_fraction=0.7)
    assert strict.attrs["n_total"] == 10 and strict.attrs["n_dropped"] == 2 and len(strict) == 8
    assert (strict["label_fraction"] >= 0.7).all()
    assert list(strict.index) == list(range(8))


def test_too_short_names_window_length():
    with pytest.raises(InputError, match=r"fewer than one window of 75 samples \(1.5 s"):
        make_windows(_rec(60))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"overlap": 1.0}, "overlap"), ({"min_label_fraction": 1.5}, "min_label_fraction"), ({"length_s": 0.01}, "shorter than 2")],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(InputError, match=match):
        make_windows(_rec(300), **kwargs)


@settings(max_examples=60, deadline=None)
@given(
    labels=st.lists(st.sampled_from(["a", "b", "c"]), min_size=8, max_size=80),
    length=st.integers(2, 8),
    overlap=st.sampled_from([0.0, 0.5, 0.75]),
)
def test_majority_matches_per_window_count(labels, length, overlap):
    rec = _rec(len(labels), np.array(labels), fs=10.0)
    w = make_windows(rec, length / 10.0, overlap, min_label_fraction=0.0)
    for _, row in w.iterrows():
        counts = Counter(labels[row["start"] : row["end"]])
        top = max(counts.values())
        assert row["label"] == min(k for k, v in counts.items() if v == top)
        assert row["label_fraction"] == pytest.approx(top / length)
