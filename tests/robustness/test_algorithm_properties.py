"""Property-based tests: degenerate and hostile signals give a correct answer or an InputError.

Targets: every step detector, every zero-velocity detector, the feature extractor,
the PDR pipeline. Signals: constant (a phone lying still), single samples, white
noise, huge spikes, sines of any frequency, random walks; any sampling rate.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gaitml import InputError
from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording
from tests.robustness._hyp import count, hyp_settings

EXAMPLES = int(os.environ.get("GAITML_HYPOTHESIS_EXAMPLES", "60"))
SETTINGS = hyp_settings(EXAMPLES)


@st.composite
def recordings(draw, min_n=1, max_n=3000):
    n = draw(st.integers(min_value=min_n, max_value=max_n))
    fs = draw(st.sampled_from([20.0, 50.0, 100.0, 204.8]))
    kind = draw(st.sampled_from(["constant", "noise", "sine", "spikes", "walk", "steps"]))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    acc = np.zeros((n, 3))
    acc[:, 2] = GRAVITY_MS2
    gyr = np.zeros((n, 3))
    if kind == "noise":
        acc += rng.normal(0, draw(st.floats(0.01, 5.0)), (n, 3))
        gyr += rng.normal(0, 0.5, (n, 3))
    elif kind == "sine":
        f = draw(st.floats(0.1, fs / 2.5))
        a = draw(st.floats(0.1, 15.0))
        acc[:, 2] += a * np.sin(2 * np.pi * f * t)
        gyr[:, 0] = np.sin(2 * np.pi * f * t)
    elif kind == "spikes":
        idx = rng.integers(0, n, size=max(1, n // 50))
        acc[idx] += rng.normal(0, 1e3, (len(idx), 3))  # up to ~300 g: inside the widest sensor range
        gyr[idx] += rng.normal(0, 30, (len(idx), 3))
    elif kind == "walk":
        acc += np.cumsum(rng.normal(0, 0.05, (n, 3)), axis=0)
        gyr += np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0)
    elif kind == "steps":
        acc[:, 2] += 3.0 * np.maximum(np.sin(2 * np.pi * 1.9 * t), 0) ** 2 - 1.0
        acc[:, 1] += 1.0 * np.sin(2 * np.pi * 1.9 * t + 1.0)
        gyr[:, 2] = 0.3 * np.sin(2 * np.pi * 0.95 * t)
    try:
        return kind, Recording(acc=acc, gyr=gyr, sampling_rate_hz=fs)
    except InputError:
        return kind, None


def _step_names():
    from gaitml.steps import detector_names

    return [d for d in detector_names()]


def _zupt_names():
    from gaitml.zupt import DETECTORS

    return list(DETECTORS)


@pytest.mark.parametrize("name", _step_names())
@SETTINGS
@given(data=recordings())
def test_step_detectors(name, data):
    from gaitml.steps import get_detector

    kind, rec = data
    if rec is None:
        count(f"steps[{name}]", "no valid recording")
        return
    try:
        steps = get_detector(name).detect(rec).steps_
    except InputError as exc:
        assert "\n" not in str(exc)
        count(f"steps[{name}]", "refused")
        return
    count(f"steps[{name}]", "ran")
    for c in ("start", "peak", "end", "t_start_s", "t_peak_s", "t_end_s", "period_s"):
        assert c in steps.columns
    if len(steps):
        assert (steps["start"] >= 0).all() and (steps["end"] <= rec.n_samples).all()
        assert (steps["start"] <= steps["peak"]).all() and (steps["peak"] <= steps["end"]).all()
        assert np.isfinite(steps["period_s"]).all() and (np.diff(steps["t_peak_s"]) >= 0).all()
    if kind == "constant":
        assert len(steps) == 0  # a still phone takes no steps


@pytest.mark.parametrize("name", _zupt_names())
@SETTINGS
@given(data=recordings())
def test_zupt_detectors(name, data):
    from gaitml.zupt import get_detector

    kind, rec = data
    if rec is None:
        count(f"zupt[{name}]", "no valid recording")
        return
    try:
        det = get_detector(name).detect(rec)
    except InputError as exc:
        assert "\n" not in str(exc)
        count(f"zupt[{name}]", "refused")
        return
    count(f"zupt[{name}]", "ran")
    mask = np.asarray(det.per_sample_zupts_)
    assert mask.shape == (rec.n_samples,) and mask.dtype == bool
    z = det.zupts_
    assert ((z["start"] >= 0) & (z["end"] <= rec.n_samples) & (z["start"] < z["end"])).all()
    assert int((z["end"] - z["start"]).sum()) == int(mask.sum())
    if kind == "constant" and rec.n_samples >= rec.sampling_rate_hz:
        assert mask.mean() > 0.9  # a still sensor is at zero velocity


@SETTINGS
@given(data=recordings(), length_s=st.sampled_from([0.5, 1.5, 3.0]), overlap=st.sampled_from([0.0, 0.5, 0.9]))
def test_features(data, length_s, overlap):
    from gaitml.features import extract_features

    kind, rec = data
    if rec is None:
        count("features", "no valid recording")
        return
    try:
        f = extract_features(rec, subset="all52+gyro", length_s=length_s, overlap=overlap)
    except InputError as exc:
        assert "\n" not in str(exc)
        count("features", "refused")
        return
    count("features", "ran")
    assert np.isfinite(f.to_numpy()).all()
    if kind == "constant" and len(f):
        assert np.allclose(f["acc_x__var"], 0) and np.allclose(f["acc_z__mean"], GRAVITY_MS2)


@hyp_settings(max(10, EXAMPLES // 2))
@given(data=recordings(), heading=st.sampled_from(["hde", "gyro", "dwpca"]))
def test_pdr(data, heading):
    from gaitml.pdr import run_pdr

    kind, rec = data
    if rec is None:
        count("pdr", "no valid recording")
        return
    try:
        res = run_pdr(rec, heading=heading, modes="forward")
    except InputError as exc:
        assert "\n" not in str(exc)
        count("pdr", "refused")
        return
    count("pdr", "ran")
    traj = res.trajectory
    assert len(traj) == res.n_steps + 1
    assert np.isfinite(traj[["x_m", "y_m", "heading_rad"]].to_numpy()).all()
    assert res.distance_m >= 0
    if kind == "constant":
        assert res.n_steps == 0 and res.end_xy_m == (0.0, 0.0)
