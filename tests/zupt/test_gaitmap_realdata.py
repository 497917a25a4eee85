"""ZUPT bars on the gaitmap example walk (both feet, motion-capture min_vel)."""

from __future__ import annotations

import pytest

from gaitml.evaluation.zupt import evaluate_stride_events
from gaitml.io import read_recording
from gaitml.zupt import DETECTORS, get_detector, segment_strides
from tests.conftest import shared

pytestmark = pytest.mark.realdata


@pytest.fixture(scope="module")
def feet():
    path = shared("gaitmap-example", "imu_sample.csv.gz")
    return {foot: read_recording(path, sensor=foot) for foot in ("left", "right")}


@pytest.mark.parametrize("foot", ["left", "right"])
def test_pseudo_std_paper_threshold(feet, foot):
    rec = feet[foot]
    r = evaluate_stride_events(get_detector("pseudo-std").detect(rec), rec.reference["stride_events"])
    assert r["min_vel_recall"] >= 0.95
    assert r["split_fraction"] <= 0.05


def test_pseudo_std_fitted_left_tested_right(feet):
    det = get_detector("pseudo-std").fit([feet["left"]])
    assert 20.0 < det.threshold_rads_ * 57.2958 < 60.0  # below the paper's 65.4 deg/s: tighter labels
    r = evaluate_stride_events(det.detect(feet["right"]), feet["right"].reference["stride_events"])
    assert r["min_vel_recall"] >= 0.95
    assert r["split_fraction"] <= 0.05


@pytest.mark.parametrize("name", list(DETECTORS))
def test_every_detector_runs_and_finds_stances(feet, name):
    for rec in feet.values():
        r = evaluate_stride_events(get_detector(name).detect(rec), rec.reference["stride_events"])
        assert r["stance_recall"] == 1.0  # every stance overlaps some detection
        assert r["n_intervals"] >= r["n_strides"]


def test_segmented_strides_match_reference_strides(feet):
    rec = feet["right"]
    ev = rec.reference["stride_events"]
    st = segment_strides(get_detector("pseudo-std").detect(rec).zupts_)
    inside = st[(st["start"] >= ev["start"].min() - 100) & (st["end"] <= ev["end"].max() + 100)]
    assert abs(len(inside) - len(ev)) <= 2
    # every reference min_vel-to-min_vel stride has a detected stride starting within 0.25 s
    import numpy as np

    d = np.abs(inside["start"].to_numpy()[None, :] - ev["start"].to_numpy()[:, None]).min(axis=1)
    assert np.mean(d / rec.sampling_rate_hz <= 0.25) >= 0.95


def test_interval_rules_bring_spurious_intervals_under_target(feet):
    """Issue 13: at the paper threshold the per-sample rule alone leaves 2 spurious intervals in 29 left
    stances (0.069: a 49 ms terminal-swing dip before a heel strike, and a real rest in the turn that
    motion capture did not annotate); the interval rules drop the dip (measured 1/29 = 0.034 left, 0 right)."""
    ev = feet["left"].reference["stride_events"]
    raw = evaluate_stride_events(get_detector("pseudo-std", merge_gap_s=0, min_interval_s=0).detect(feet["left"]), ev)
    assert raw["n_spurious"] == 2 and raw["spurious_per_stance"] == pytest.approx(2 / 29)
    for foot, rec in feet.items():
        r = evaluate_stride_events(get_detector("pseudo-std").detect(rec), rec.reference["stride_events"])
        assert r["spurious_per_stance"] <= 0.05, foot  # measured 0.034 (left), 0.0 (right)
        assert r["min_vel_recall"] == 1.0, foot
