"""Gyroscope bias: estimated from still stretches, tracked online while the tilt is steady, removed before the heading."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.pdr import run_pdr
from gaitml.pdr.attitude import AttitudeEstimator
from gaitml.recording import Recording
from gaitml.signal import estimate_gyro_bias, steady_tilt_mask

FS = 100.0
BIAS = np.array([0.05, -0.03, 0.02])  # rad/s, of the order of the raw iOS gyroscopes'


def _flat_phone(still_s: float, turn_s: float, rate_rads: float = 0.3, seed: int = 0, bias=BIAS):
    """A phone lying flat (z up): still, then turning about the vertical at a constant rate; biased gyro."""
    rng = np.random.default_rng(seed)
    n_still, n_turn = int(still_s * FS), int(turn_s * FS)
    n = n_still + n_turn
    acc = np.tile([0.0, 0.0, GRAVITY_MS2], (n, 1)) + rng.normal(0, 0.02, (n, 3))
    w = np.zeros((n, 3))
    w[n_still:, 2] = rate_rads
    gyr = w + np.asarray(bias) + rng.normal(0, 0.003, (n, 3))
    return Recording.from_arrays(acc, FS, gyr=gyr), w


def _true_heading(w):
    # body rate about z (up) turns the forward axis counter-clockwise: compass heading decreases
    return -np.cumsum(w[:, 2]) / FS


def test_still_stretch_gives_the_bias():
    rec, _ = _flat_phone(still_s=5.0, turn_s=20.0)
    gb = estimate_gyro_bias(rec.acc, rec.gyr, FS)
    assert gb.method == "still"
    assert gb.still_s >= 4.0
    np.testing.assert_allclose(gb.bias_rads, BIAS, atol=0.003)
    d = gb.to_dict()
    assert json.loads(json.dumps(d))["method"] == "still" and "removed" in d["note"]


def test_no_still_stretch_removes_nothing_and_says_so():
    rng = np.random.default_rng(1)
    n = int(30 * FS)
    t = np.arange(n) / FS
    acc = np.tile([0.0, 0.0, GRAVITY_MS2], (n, 1))
    acc[:, 2] += 3.0 * np.sin(2 * np.pi * 1.8 * t)  # walking bounce all the time
    gyr = BIAS + 0.5 * np.sin(2 * np.pi * 0.9 * t)[:, None] + rng.normal(0, 0.003, (n, 3))
    gb = estimate_gyro_bias(acc, gyr, FS)
    assert gb.method == "none"
    assert np.all(gb.bias_rads == 0)
    assert "not removed" in gb.note


def test_bad_shapes_are_one_line_errors():
    with pytest.raises(InputError, match="shape"):
        estimate_gyro_bias(np.zeros((10, 3)), np.zeros((10, 2)), FS)
    with pytest.raises(InputError, match="gyro_bias"):
        AttitudeEstimator(gyro_bias="sometimes").estimate(_flat_phone(2.0, 2.0)[0])


@pytest.mark.parametrize("mode", ["still", "auto"])
def test_removing_the_bias_cuts_the_heading_drift(mode):
    rec, w = _flat_phone(still_s=5.0, turn_s=60.0)
    truth = _true_heading(w)
    errs = {}
    for m in ("off", mode):
        att = AttitudeEstimator(gyro_bias=m).estimate(rec)
        err = np.unwrap(att.heading_rad_) - truth
        errs[m] = abs(err[-1] - err[0])
    # the z bias (0.02 rad/s) over 65 s is about 75 deg of drift; the estimate removes at least 90 % of it
    assert errs["off"] > np.radians(60)
    assert errs[mode] < 0.1 * errs["off"]


def test_online_tracking_learns_the_horizontal_bias_without_a_still_stretch():
    """Phone flat and turning all the time (never still): gravity reveals the bias across the vertical."""
    rec, _ = _flat_phone(still_s=0.0, turn_s=120.0, rate_rads=0.2)
    assert estimate_gyro_bias(rec.acc, rec.gyr, FS).method == "none"
    assert steady_tilt_mask(rec.acc, rec.gyr, FS).mean() > 0.9
    on = AttitudeEstimator().estimate(rec)
    off = AttitudeEstimator(gyro_bias="off").estimate(rec)
    assert on.gyro_bias_.method == "online"
    np.testing.assert_allclose(on.bias_rads_[-1, :2], BIAS[:2], atol=0.01)
    up = np.array([0.0, 0.0, 1.0])

    def tilt(att):
        return np.degrees(np.arccos(np.clip(att.rotation_.inv().apply(up) @ up, -1, 1)))

    assert tilt(on)[-1000:].mean() < 0.5 * tilt(off)[-1000:].mean()


def test_run_pdr_and_cli_say_what_was_removed(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    rec, _ = _flat_phone(still_s=5.0, turn_s=10.0)
    res = run_pdr(rec, modes="forward", heading="gyro", detector="adaptive")
    assert res.info["gyro_bias"]["method"] in ("still", "still+online")
    assert res.to_json_dict()["gyro_bias"]["bias_rads"] == res.info["gyro_bias"]["bias_rads"]
    off = run_pdr(rec, modes="forward", heading="gyro", detector="adaptive", gyro_bias="off")
    assert off.info["gyro_bias"]["method"] == "off"
    path = tmp_path / "rec.csv"
    write_gaitml_csv(rec, path)
    for mode in ("off", "still"):
        capsys.readouterr()
        assert main(["pdr", str(path), "--gyro-bias", mode, "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["gyro_bias"]["method"] == mode


def test_one_default_step_detector_for_steps_pdr_label_segment():
    """`gaitml steps`, `pdr`, `label` and `segment --by steps` (and the library calls) share one default."""
    import argparse
    import inspect

    from gaitml.chunked_run import long_pdr, long_steps
    from gaitml.cli import build_parser
    from gaitml.commands.pdr import _detector
    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.segment import DEFAULT_DETECTORS

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    steps_opt = next(a for a in sub.choices["steps"]._actions if "--detector" in a.option_strings)
    assert steps_opt.default == DEFAULT_STEP_DETECTOR
    assert _detector(argparse.Namespace(detector=None), None, []) == DEFAULT_STEP_DETECTOR
    assert DEFAULT_DETECTORS["steps"] == DEFAULT_STEP_DETECTOR
    for fn in (run_pdr, long_pdr, long_steps):
        assert inspect.signature(fn).parameters["detector"].default == DEFAULT_STEP_DETECTOR


def test_a_given_bias_array_continues_a_chunk_like_a_list():
    """``gyro_bias`` as a (3,) array works in estimate_from (the chunked path) as a list does."""
    from scipy.spatial.transform import Rotation

    rec, _ = _flat_phone(still_s=2.0, turn_s=10.0)
    heads = []
    for given in (BIAS, list(BIAS)):
        att = AttitudeEstimator(gyro_bias=given).estimate_from(rec, 300, Rotation.identity(), initial_bias_rads=BIAS)
        assert att.gyro_bias_.method == "carried"
        heads.append(att.heading_rad_)
    np.testing.assert_allclose(heads[0], heads[1])
