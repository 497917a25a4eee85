"""Zero-velocity detectors: known answers, vectorised == per-sample reference, API, errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.consts import GRAVITY_MS2, ZUPT_COLUMNS
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.zupt import (
    DETECTORS,
    PAPER_THRESHOLD_RADS,
    PseudoStdZuptDetector,
    ShoeZuptDetector,
    detect_zupts,
    get_detector,
    intervals_table,
    intervals_to_mask,
    magnitude_zupts,
    mask_runs,
    np_threshold,
    pseudo_std,
    pseudo_std_tangent,
    remove_short_runs,
    shoe_statistic,
)
from gaitml.zupt.pseudo_std import PAPER_EPS, PAPER_MU1_RADS, PAPER_S1_RADS, fit_zero_velocity_normal
from tests.reference import zupt as ref
from tests.synthetic import synthetic_foot_walk


# ---------------------------------------------------------------- paper 001
@pytest.mark.parametrize("s", [1, 2, 5, 10])
def test_pseudo_std_equals_std_of_zero_padded_window(s):
    """Paper 001 eqs. 6-7: sigma'(i) is the std of the window extended with 2s+1 zeros."""
    rng = np.random.default_rng(s)
    g = rng.gamma(2.0, 0.5, size=200)
    got = pseudo_std(g, s)
    for i in range(s, len(g) - s):  # full windows
        padded = np.concatenate([np.zeros(2 * s + 1), g[i - s : i + s + 1]])
        assert got[i] == pytest.approx(np.std(padded), rel=1e-9, abs=1e-12)
    # at the edges: the truncated window padded with as many zeros
    win = g[: s + 1]
    assert got[0] == pytest.approx(np.std(np.concatenate([np.zeros(len(win)), win])), rel=1e-9)


def test_pseudo_std_closed_form_eq8_on_linear_signal():
    """On g = k t + b, the exact pseudo-std equals eq. (8) sqrt(g^2/4 + k^2 s(s+1)/6)."""
    s = 4
    t = np.arange(100, dtype=float)
    g = 0.03 * t + 0.7
    exact = pseudo_std(g, s)[s:-s]
    closed = np.sqrt(g**2 / 4 + 0.03**2 * s * (s + 1) / 6)[s:-s]
    np.testing.assert_allclose(exact, closed, rtol=1e-9)
    np.testing.assert_allclose(pseudo_std_tangent(g, s)[s:-s], closed, rtol=1e-9)


def test_np_threshold_reproduces_paper_65_40_degs():
    """Paper 001 eq. (16): 27.75 + u_0.998 * 13.07 = 65.40 deg/s."""
    thr_degs = np.degrees(np_threshold(PAPER_MU1_RADS, PAPER_S1_RADS, PAPER_EPS))
    assert thr_degs == pytest.approx(65.40, abs=0.05)  # exact quantile 2.878 -> 65.37
    assert 27.75 + round(2.878162, 2) * 13.07 == pytest.approx(65.40, abs=0.01)  # the paper's rounded u = 2.88
    assert np.degrees(PAPER_THRESHOLD_RADS) == pytest.approx(65.40)
    assert PseudoStdZuptDetector().detect(synthetic_foot_walk(500)).threshold_rads_ == pytest.approx(1.14145, abs=1e-4)


def test_fit_is_maximum_likelihood_normal():
    rng = np.random.default_rng(1)
    v = rng.normal(0.5, 0.2, 20000)
    mu, s1 = fit_zero_velocity_normal(v)
    assert mu == pytest.approx(v.mean()) and s1 == pytest.approx(v.std(ddof=0))
    assert mu == pytest.approx(0.5, abs=0.01) and s1 == pytest.approx(0.2, abs=0.01)


def test_pseudo_std_fit_sets_np_threshold_from_labelled_samples():
    rec = synthetic_foot_walk(3000)
    phase = (np.arange(3000) / 100.0) % 1.0
    label = (phase > 0.1) & (phase < 0.3)  # mid-stance of the synthetic walk
    det = PseudoStdZuptDetector(eps=0.01).fit([rec], [label])
    vals = pseudo_std(np.linalg.norm(rec.gyr, axis=1), 5)[label]
    assert det.mu1_rads_ == pytest.approx(vals.mean())
    assert det.s1_rads_ == pytest.approx(vals.std())
    assert det.threshold_rads_ == pytest.approx(vals.mean() + 2.326348 * vals.std(), rel=1e-5)
    det.detect(rec)
    assert det.threshold_rads_ == pytest.approx(det.fitted_threshold_rads_)
    assert det.per_sample_zupts_[label].mean() > 0.99


def test_half_window_scales_with_rate():
    for fs, s in ((100.0, 5), (204.8, 10), (50.0, 2)):
        rec = Recording(acc=np.tile([0, 0, GRAVITY_MS2], (150, 1)), gyr=np.zeros((150, 3)), sampling_rate_hz=fs)
        from gaitml.zupt._intervals import half_window_samples

        assert half_window_samples(PseudoStdZuptDetector().half_window_s, fs) == s
        assert PseudoStdZuptDetector().detect(rec).per_sample_zupts_.all()


# ---------------------------------------------------------------- SHOE
def test_shoe_statistic_zero_for_still_imu_any_orientation():
    rng = np.random.default_rng(0)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    acc = np.tile(GRAVITY_MS2 * u, (40, 1))
    t = shoe_statistic(acc, np.zeros((40, 3)), 1)
    np.testing.assert_allclose(t, 0.0, atol=1e-6)


def test_shoe_statistic_gyro_term():
    gyr = np.zeros((30, 3))
    gyr[:, 2] = 0.01
    acc = np.tile([0.0, 0.0, GRAVITY_MS2], (30, 1))
    t = shoe_statistic(acc, gyr, 1, sigma_w_rads=0.1)
    np.testing.assert_allclose(t, (0.01 / 0.1) ** 2, rtol=1e-6)


# ---------------------------------------------------------------- vectorised == reference loops
@pytest.mark.parametrize("name", list(DETECTORS))
def test_vectorised_equals_per_sample_reference(name):
    rec = synthetic_foot_walk(1500, seed=3)
    det = get_detector(name)
    got = det.detect(rec).per_sample_zupts_
    fs = rec.sampling_rate_hz
    acc, gyr = rec.acc, rec.gyr
    if name == "pseudo-std":
        np.testing.assert_allclose(det.statistic_, ref.reference_pseudo_std(gyr, 5), rtol=1e-9, atol=1e-12)
        want = ref.reference_pseudo_std(gyr, 5) < PAPER_THRESHOLD_RADS
    elif name == "shoe":
        stat = ref.reference_shoe(acc, gyr, 1, det.sigma_a_ms2, det.sigma_w_rads)
        np.testing.assert_allclose(det.statistic_, stat, rtol=1e-6, atol=1e-3)
        want = stat < det.gamma
    elif name == "gyro-range":
        want = ref.reference_gyro_range(acc, gyr, 5, det.gyr_range_rads, det.acc_max_ms2)
    elif name == "magnitude-std":
        want = ref.reference_magnitude_std(
            acc, gyr, 5, det.acc_min_ms2, det.acc_max_ms2, det.acc_std_ms2, det.gyr_max_rads, det.gyr_std_rads
        )
    else:
        want = ref.reference_magnitude(acc, fs, det.t_min_ms2, det.t_max_ms2, det.min_run_fraction)
    np.testing.assert_array_equal(got, want)
    assert 0.05 < got.mean() < 0.95  # the synthetic walk exercises both decisions


# ---------------------------------------------------------------- paper 004
def test_magnitude_rejects_runs_shorter_than_ten_percent_of_fs():
    fs = 50.0  # 10 % of fs = 5 samples
    a = np.full(60, 15.0)
    a[5:10] = GRAVITY_MS2  # 5 samples: kept
    a[20:24] = GRAVITY_MS2  # 4 samples: pseudo-zero, rejected
    a[30:50] = GRAVITY_MS2
    m = magnitude_zupts(a, fs)
    s, e = mask_runs(m)
    assert list(zip(s, e, strict=True)) == [(5, 10), (30, 50)]


def test_magnitude_band_is_open():
    a = np.array([9.0, 9.5, 11.0, 10.0])
    assert magnitude_zupts(a, 1.0, min_run_fraction=0).tolist() == [False, True, False, True]


# ---------------------------------------------------------------- intervals
def test_interval_helpers_roundtrip():
    m = np.array([1, 1, 0, 0, 1, 0, 1, 1, 1], dtype=bool)
    s, e = mask_runs(m)
    assert s.tolist() == [0, 4, 6] and e.tolist() == [2, 5, 9]
    np.testing.assert_array_equal(intervals_to_mask(s, e, len(m)), m)
    np.testing.assert_array_equal(remove_short_runs(m, 2), [1, 1, 0, 0, 0, 0, 1, 1, 1])
    t = intervals_table(m, 2.0)
    assert tuple(t.columns) == ZUPT_COLUMNS
    assert t["t_end_s"].tolist() == [1.0, 2.5, 4.5]
    assert len(intervals_table(np.zeros(5, bool), 10.0)) == 0


# ---------------------------------------------------------------- API and errors
@pytest.mark.parametrize("name", list(DETECTORS))
def test_detector_api(name):
    rec = synthetic_foot_walk(1000)
    det = get_detector(name)
    assert det.detect(rec) is det
    assert det.per_sample_zupts_.dtype == bool and det.per_sample_zupts_.shape == (1000,)
    assert isinstance(det.zupts_, pd.DataFrame) and tuple(det.zupts_.columns) == ZUPT_COLUMNS
    z = det.zupts_
    np.testing.assert_array_equal(intervals_to_mask(z["start"], z["end"], 1000), det.per_sample_zupts_)
    assert (z["end"] > z["start"]).all()
    assert det.name == name
    assert repr(det).startswith(type(det).__name__)
    assert detect_zupts(rec, detector=name, return_detector=True).per_sample_zupts_.sum() == det.per_sample_zupts_.sum()


def test_get_detector_unknown_name_lists_names():
    with pytest.raises(InputError, match="pseudo-std, magnitude, gyro-range, magnitude-std, shoe"):
        get_detector("nope")
    with pytest.raises(InputError, match="bad parameters"):
        get_detector("shoe", threshold_rads=1.0)


@pytest.mark.parametrize("name", ["pseudo-std", "gyro-range", "magnitude-std", "shoe"])
def test_gyro_detectors_need_gyro(name):
    rec = Recording(acc=np.tile([0, 0, GRAVITY_MS2], (100, 1)), sampling_rate_hz=100.0)
    with pytest.raises(InputError, match="needs a gyroscope"):
        get_detector(name).detect(rec)


def test_magnitude_works_without_gyro():
    rec = Recording(acc=np.tile([0, 0, GRAVITY_MS2], (100, 1)), sampling_rate_hz=100.0)
    assert get_detector("magnitude").detect(rec).per_sample_zupts_.all()


@pytest.mark.parametrize(
    ("name", "params", "match"),
    [
        ("pseudo-std", {"threshold_rads": -1.0}, "threshold_rads"),
        ("pseudo-std", {"half_window_s": 0.0}, "half_window_s"),
        ("pseudo-std", {"form": "x"}, "form"),
        ("magnitude", {"t_min_ms2": 11.0, "t_max_ms2": 9.0}, "t_min_ms2"),
        ("shoe", {"window_samples": 4}, "odd"),
        ("shoe", {"gamma": 0.0}, "gamma"),
    ],
)
def test_bad_parameters_raise_input_error(name, params, match):
    with pytest.raises(InputError, match=match):
        get_detector(name, **params).detect(synthetic_foot_walk(300))


def test_fit_errors():
    rec = synthetic_foot_walk(300)
    with pytest.raises(InputError, match="no zero-velocity reference"):
        PseudoStdZuptDetector().fit([rec])
    with pytest.raises(InputError, match="shape"):
        ShoeZuptDetector().fit([rec], [np.ones(10, bool)])
    with pytest.raises(InputError, match="at least 2"):
        PseudoStdZuptDetector().fit([rec], [np.zeros(300, bool)])


@pytest.mark.parametrize("name", ["magnitude", "shoe"])
def test_quantile_fit_keeps_labelled_samples(name):
    rec = synthetic_foot_walk(3000)
    phase = (np.arange(3000) / 100.0) % 1.0
    label = (phase > 0.1) & (phase < 0.3)
    det = get_detector(name, eps=0.01).fit([rec], [label]).detect(rec)
    assert det.per_sample_zupts_[label].mean() >= 0.98


@pytest.mark.parametrize("name", ["pseudo-std", "gyro-range", "magnitude-std", "magnitude", "shoe"])
@pytest.mark.parametrize("n", [2, 10])
def test_too_short_recording_is_refused(name, n):
    rec = synthetic_foot_walk(300).slice(0, n)
    with pytest.raises(InputError, match=rf"too short for the {name} detector: {n} samples < \d+ needed.*use a longer recording"):
        get_detector(name).detect(rec)


def test_shortest_accepted_recording_is_one_window_and_half_a_second():
    rec = synthetic_foot_walk(300)
    fs = rec.sampling_rate_hz
    det = get_detector("pseudo-std", half_window_s=0.5)
    n_min = det.min_samples(fs)
    assert n_min == 2 * round(0.5 * fs) + 1
    det.detect(rec.slice(0, n_min))
    with pytest.raises(InputError, match="too short"):
        det.detect(rec.slice(0, n_min - 1))
    assert get_detector("pseudo-std").min_samples(fs) == int(np.ceil(0.5 * fs))
