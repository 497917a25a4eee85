"""ZUPT metrics (gaitml.evaluation.zupt) and stride segmentation (gaitml.zupt.segment_strides)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.evaluation.zupt import (
    count_accuracy,
    evaluate_stride_events,
    interval_recall,
    over_segmentation,
    per_sample_scores,
    point_recall,
)
from gaitml.zupt import intervals_table, label_strides, segment_strides


def test_per_sample_scores_known_answer():
    ref = np.array([1, 1, 1, 1, 0, 0, 0, 0, 0, 0], bool)
    pred = np.array([1, 1, 1, 0, 1, 0, 0, 0, 0, 0], bool)
    s = per_sample_scores(pred, ref)
    assert (s["tp"], s["fp"], s["fn"], s["tn"]) == (3, 1, 1, 5)
    assert s["accuracy"] == pytest.approx(0.8)
    assert s["precision"] == pytest.approx(0.75) and s["recall"] == pytest.approx(0.75) and s["f1"] == pytest.approx(0.75)
    with pytest.raises(InputError):
        per_sample_scores(pred[:5], ref)


def test_point_and_interval_recall_and_over_segmentation():
    det = pd.DataFrame({"start": [10, 30, 36, 80], "end": [20, 34, 45, 90]})
    rec, hit = point_recall(det, [15, 20, 33, 40, 60])
    assert hit.tolist() == [True, False, True, True, False]  # end is exclusive
    assert rec == pytest.approx(0.6)
    ref_s, ref_e = np.array([5, 28, 55]), np.array([25, 50, 70])
    assert interval_recall(det, ref_s, ref_e) == pytest.approx(2 / 3)
    seg = over_segmentation(det, ref_s, ref_e)
    assert seg["counts"].tolist() == [1, 2, 0]
    assert seg["split_fraction"] == pytest.approx(1 / 3)
    assert seg["mean_per_reference"] == pytest.approx(1.0)
    # a bool mask works the same
    mask = np.zeros(100, bool)
    mask[10:20] = True
    assert point_recall(mask, [12, 25])[0] == 0.5


def test_count_accuracy_reproduces_paper_001_table_1():
    assert 100 * count_accuracy(88, 87) == pytest.approx(98.9, abs=0.05)  # subject A, slow, method 3
    assert 100 * count_accuracy(38, 72) == pytest.approx(52.8, abs=0.05)  # subject B, jog, method 1
    assert 100 * count_accuracy(57, 77) == pytest.approx(74.0, abs=0.05)  # subject A, jog, method 2
    with pytest.raises(InputError):
        count_accuracy(3, 0)


def test_evaluate_stride_events_synthetic():
    ev = pd.DataFrame({"start": [100, 200], "end": [200, 300], "min_vel": [100, 200], "pre_ic": [80, 180], "tc": [130, 230]})
    mask = np.zeros(400, bool)
    mask[85:125] = True
    mask[185:200] = True
    mask[205:225] = True  # stance 2 split in two
    mask[290:310] = True
    r = evaluate_stride_events(intervals_table(mask, 100.0), ev)
    assert r["min_vel_recall"] == 0.5  # min_vel 200 falls in the gap
    assert r["split_fraction"] == 0.5
    assert r["stride_extra_fraction"] == 0.5  # stride 2 holds the starts 205 and 290
    assert r["n_stances_in_span"] == 3 and r["n_intervals_in_span"] == 4
    assert r["count_accuracy"] == pytest.approx(1 - 1 / 3)


def test_segment_strides_between_consecutive_intervals():
    mask = np.zeros(100, bool)
    mask[0:10] = mask[30:40] = mask[60:80] = True
    st = segment_strides(mask, 10.0)
    assert st[["start", "end"]].to_numpy().tolist() == [[5, 35], [35, 70]]
    assert st[["stance_start", "stance_end", "swing_start", "swing_end"]].to_numpy().tolist() == [[0, 10, 10, 30], [30, 40, 40, 60]]
    assert st["duration_s"].tolist() == [3.0, 3.5]
    assert len(segment_strides(intervals_table(mask, 10.0), max_stride_s=3.2)) == 1
    lab = label_strides(st, 100)
    assert (lab[5:35] == 0).all() and (lab[35:70] == 1).all() and (lab[:5] == -1).all() and (lab[70:] == -1).all()
    with pytest.raises(InputError, match="sampling_rate_hz"):
        segment_strides(mask)


def test_segment_strides_empty_and_single():
    assert len(segment_strides(np.zeros(10, bool), 10.0)) == 0
    m = np.zeros(10, bool)
    m[2:4] = True
    assert len(segment_strides(m, 10.0)) == 0
