"""Step-synchronous windows: one window per detected step, labels per step, features on the step's own samples."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.features import extract_features, extract_step_features, feature_names, make_step_windows
from gaitml.features.step_windows import MIN_SPAN_SAMPLES, check_window_by, spans_from_steps, step_raw_windows, step_spans
from gaitml.simulate import simulate_dataset
from gaitml.steps import get_detector


@pytest.fixture(scope="module")
def rec():
    return simulate_dataset(n_subjects=1, duration_s=40.0, seed=11, segment_s=(6.0, 9.0))[0]


def test_one_window_per_detected_step_and_spans_tile(rec):
    steps = get_detector("single-peak").detect(rec).steps_
    w = make_step_windows(rec, "steps", "single-peak", min_label_fraction=0.0)
    assert len(steps) > 40
    assert len(w) + w.attrs["n_short"] == len(steps)
    assert np.all(np.diff(w["step"].to_numpy()) > 0) and set(w["step"]) <= set(range(len(steps)))
    # each window ends right after its step's peak and starts right after the previous peak (or the cap)
    np.testing.assert_array_equal(w["end"].to_numpy(), steps["peak"].to_numpy()[w["step"]] + 1)
    s, e = w["start"].to_numpy(), w["end"].to_numpy()
    gap = s[1:] != e[:-1]
    assert np.all((e[1:] - s[1:])[gap] == round(2.0 * rec.sampling_rate_hz))  # only capped spans (after a pause) leave a gap
    assert np.all(e - s >= MIN_SPAN_SAMPLES)
    assert w.attrs["by"] == "steps" and w.attrs["detector"] == "single-peak"


def test_window_label_is_the_majority_of_the_steps_samples(rec):
    w = make_step_windows(rec, "steps", "ifsm", min_label_fraction=0.0)
    for row in w.itertuples():
        vals, counts = np.unique(rec.labels[row.start : row.end], return_counts=True)
        assert row.label == vals[np.argmax(counts)]
        assert row.label_fraction == pytest.approx(counts.max() / (row.end - row.start))
    assert set(w["label"]) == set(rec.labels)  # every mode of the walk has steps
    assert (w["label_fraction"] < 1).sum() >= 1  # steps across a mode change are mixed


def test_min_label_fraction_drops_mixed_steps(rec):
    all_ = make_step_windows(rec, "steps", min_label_fraction=0.0)
    pure = make_step_windows(rec, "steps", min_label_fraction=1.0)
    assert len(pure) == int((all_["label_fraction"] == 1.0).sum())
    assert pure.attrs["n_dropped"] == len(all_) - len(pure) > 0


def test_features_are_those_of_the_steps_own_samples(rec):
    w = make_step_windows(rec, "steps", min_label_fraction=0.0)
    feats = extract_step_features(rec, w, subset="all52+gyro")
    assert list(feats.columns) == feature_names("all52+gyro") and len(feats) == len(w)
    lengths = (w["end"] - w["start"]).to_numpy()
    assert len(np.unique(lengths)) > 3  # steps of different lengths
    for i in [0, 5, len(w) // 2, len(w) - 1]:
        a, b = int(w["start"].iloc[i]), int(w["end"].iloc[i])
        # the time-window extractor over the same sample span of the recording
        same_span = extract_features(rec, pd.DataFrame({"start": [a], "end": [b]}), subset="all52+gyro")
        np.testing.assert_allclose(feats.iloc[i].to_numpy(), same_span.iloc[0].to_numpy(), rtol=1e-12, atol=1e-12)
        # ... and a recording holding only the step's samples (nothing from outside the step is used)
        own = rec.slice(a, b)
        alone = extract_features(own, pd.DataFrame({"start": [0], "end": [b - a]}), subset="all52+gyro")
        np.testing.assert_allclose(feats.iloc[i].to_numpy(), alone.iloc[0].to_numpy(), rtol=1e-9, atol=1e-9)


def test_spans_cap_a_step_after_a_pause():
    fs = 50.0
    steps = pd.DataFrame({"peak": [100, 125, 400], "t_peak_s": [2.0, 2.5, 8.0]})
    sp = spans_from_steps(steps, 500, fs, max_step_s=2.0)
    assert sp["start"].tolist() == [76, 101, 401 - 100]
    assert sp["end"].tolist() == [101, 126, 401]


def test_raw_step_windows_are_resampled_linearly():
    sig = np.column_stack([np.arange(100.0), 2.0 * np.arange(100.0)])
    w = pd.DataFrame({"start": [10, 40], "end": [21, 71]})
    out = step_raw_windows(sig, w, 32)
    assert out.shape == (2, 32, 2)
    np.testing.assert_allclose(out[0, :, 0], np.linspace(10, 20, 32))
    np.testing.assert_allclose(out[1, :, 1], 2 * np.linspace(40, 70, 32))


def test_stride_windows_from_a_zero_velocity_detector():
    from gaitml.zupt import get_detector as zupt_detector
    from gaitml.zupt import segment_strides

    rec = simulate_dataset(n_subjects=1, duration_s=30.0, seed=3, modes=("walk",))[0]
    # a hand-held phone has no stance phase for pseudo-std (a foot sensor's detector); magnitude-std finds one per step here
    w = make_step_windows(rec, "strides", "magnitude-std", min_label_fraction=0.0)
    strides = segment_strides(zupt_detector("magnitude-std").detect(rec).zupts_, rec.sampling_rate_hz, max_stride_s=4.0)
    assert len(strides) > 20 and len(w) + w.attrs["n_short"] == len(strides)
    np.testing.assert_array_equal(w["start"].to_numpy(), strides["start"].to_numpy()[w["step"]])
    np.testing.assert_array_equal(w["end"].to_numpy(), strides["end"].to_numpy()[w["step"]])
    assert w.attrs["by"] == "strides" and set(w["label"]) <= {"walk"}
    with pytest.raises(InputError, match="gyroscope|gyro"):
        step_spans(rec.replace(gyr=None), "strides", "pseudo-std")


@pytest.mark.parametrize(
    "by, det, match",
    [
        ("windows", None, "not known"),
        ("steps", "pseudo-std", "not a step detector"),
        ("strides", "single-peak", "not a zero-velocity detector"),
    ],
)
def test_check_window_by_refuses_names_from_the_wrong_registry(by, det, match):
    with pytest.raises(InputError, match=match) as e:
        check_window_by(by, det)
    assert "\n" not in str(e.value)


def test_default_detectors():
    assert check_window_by("steps", "") == "single-peak"
    assert check_window_by("strides", None) == "pseudo-std"
    assert check_window_by("time", "ifsm") == ""
