"""Known-answer tests: closed-form values of every feature on constant, ramp and sine windows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gaitml.features import CATALOGUE, feature_names, features_from_arrays

N = 75  # 1.5 s at 50 Hz
NAMES = feature_names("all52")
G = 9.8


def _one(acc: np.ndarray) -> dict[str, float]:
    row = features_from_arrays(acc, None, 50.0, [0], len(acc), "all52")[0]
    return dict(zip(NAMES, row, strict=True))


def _check(got: dict[str, float], expected: dict[str, float]) -> None:
    for name, value in expected.items():
        assert got[name] == pytest.approx(value, rel=1e-9, abs=1e-9), name


def _embed(acc: np.ndarray, before: int = 13, after: int = 7) -> np.ndarray:
    """The same window with unrelated samples around it (features must not see them)."""
    rng = np.random.default_rng(5)
    pad = lambda k: rng.normal(0, 3, (k, 3)) + [0, 0, G]  # noqa: E731
    return np.concatenate([pad(before), acc, pad(after)])


def test_constant_window_every_feature():
    c = np.array([1.23, -4.56, 7.89])
    acc = np.tile(c, (N, 1))
    cm = math.sqrt(float(c @ c)) - G
    vals = [*c, cm]
    modes = [1.2, -4.6, 7.9, -0.6]
    exp: dict[str, float] = {}
    for k, ax in enumerate(("x", "y", "z", "mag")):
        v = vals[k]
        exp |= {
            f"acc_{ax}__mean": v,
            f"acc_{ax}__mean_abs": abs(v),
            f"acc_{ax}__var": 0.0,
            f"acc_{ax}__mode": modes[k],
            f"acc_{ax}__max": v,
            f"acc_{ax}__min": v,
            f"acc_{ax}__iqr": 0.0,
            f"acc_{ax}__q3": v,
            f"acc_{ax}__skew": 0.0,
            f"acc_{ax}__kurt": 0.0,
            f"acc_{ax}__mad": 0.0,
            f"acc_{ax}__m4": 0.0,
        }
    exp |= {"acc_xy__corr": 0.0, "acc_xz__corr": 0.0, "acc_yz__corr": 0.0, "acc_x__f1": 0.0}
    assert set(exp) == set(NAMES)  # every one of the 52
    got = _one(acc)
    assert all(np.isfinite(list(got.values())))
    _check(got, exp)
    # the same window inside a longer signal
    row = features_from_arrays(_embed(acc), None, 50.0, [13], N, "all52")[0]
    _check(dict(zip(NAMES, row, strict=True)), exp)


def _ramp_stats(a: float, b: float, n: int) -> dict[str, float]:
    """Closed forms for the ramp a + b i, i = 0..n-1 (n odd)."""
    m = (n - 1) // 2
    first, last = a, a + b * (n - 1)
    lo, hi = min(first, last), max(first, last)
    return {
        "mean": a + b * (n - 1) / 2,
        "var": b * b * (n * n - 1) / 12,
        "max": hi,
        "min": lo,
        "iqr": abs(b) * (n - 1) / 2,
        "q3": lo + abs(b) * 0.75 * (n - 1),
        "skew": 0.0,
        "kurt": -6 * (n * n + 1) / (5 * (n * n - 1)),
        "mad": abs(b) * m * (m + 1) / n,
        "m4": 0.0,
        "f1": b * b * (n - 1) / n,
    }


def test_ramp_xyz_every_axis_feature():
    i = np.arange(N)
    # slopes of 0.22 and 0.12 put every sample in its own 0.1-wide mode bin, away from bin edges
    x = 0.32 + 0.22 * i
    y = -1.04 - 0.22 * i
    z = G + 0.12 * i
    acc = np.column_stack([x, y, z])
    exp: dict[str, float] = {}
    for ax, (a, b, mode) in {"x": (0.32, 0.22, 0.3), "y": (-1.04, -0.22, -17.3), "z": (G, 0.12, 9.8)}.items():
        r = _ramp_stats(a, b, N)
        exp |= {f"acc_{ax}__{k}": v for k, v in r.items() if k != "f1"}
        exp[f"acc_{ax}__mean_abs"] = abs(r["mean"])  # one sign throughout
        exp[f"acc_{ax}__mode"] = mode  # all bins hold one sample: the smallest value's bin
    exp["acc_x__f1"] = _ramp_stats(0.32, 0.22, N)["f1"]
    exp |= {"acc_xy__corr": -1.0, "acc_xz__corr": 1.0, "acc_yz__corr": -1.0}
    _check(_one(acc), exp)
    row = features_from_arrays(_embed(acc), None, 50.0, [13], N, "all52")[0]
    _check(dict(zip(NAMES, row, strict=True)), exp)


def test_ramp_magnitude_every_feature():
    """acc = (0, 0, g + b i): the raw magnitude is the ramp b i; the 3-sample average
    keeps the interior and moves the first/last sample by +b/2 / -b/2."""
    b = 0.22
    i = np.arange(N)
    acc = np.column_stack([np.zeros(N), np.zeros(N), G + b * i])
    r = _ramp_stats(0.0, b, N)
    mu = r["mean"]
    d = b * (N - 1) / 2  # distance of the ramp ends from the mean
    m = (N - 1) // 2
    var = r["var"] + b * b * (1.5 - N) / N
    sum4_ramp = 2 * b**4 * m * (m + 1) * (2 * m + 1) * (3 * m * m + 3 * m - 1) / 30
    m4c = (sum4_ramp + 2 * ((d - b / 2) ** 4 - d**4)) / N
    h1, h3 = 0.25 * (N - 1), 0.75 * (N - 1)  # 18.5 and 55.5: interior order statistics
    exp = {
        "acc_mag__mean": mu,
        "acc_mag__mean_abs": mu,
        "acc_mag__var": var,
        "acc_mag__mode": 0.1,  # smallest value b/2 = 0.11, every bin holds one sample
        "acc_mag__max": b * (N - 1.5),
        "acc_mag__min": b / 2,
        "acc_mag__iqr": b * (h3 - h1),
        "acc_mag__q3": b * h3,
        "acc_mag__skew": 0.0,
        "acc_mag__kurt": m4c / var**2 - 3,
        "acc_mag__mad": r["mad"] - b / N,
        "acc_mag__m4": 2 * (b / 2) ** 2 / N,
        # x, y constant zero
        "acc_x__var": 0.0,
        "acc_xz__corr": 0.0,
        "acc_x__f1": 0.0,
        "acc_z__mean": G + mu,
    }
    _check(_one(acc), exp)


def test_sine_every_statistic():
    """x = sin, y = -2 sin, z = g + 0.5 cos over 3 full periods of 25 samples (2 Hz at 50 Hz)."""
    p = 25
    w = 2 * np.pi / p
    th = w * np.arange(N)
    s = np.sin(th)
    acc = np.column_stack([s, -2 * s, G + 0.5 * np.cos(th)])
    mean_abs = 1 / math.tan(math.pi / (2 * p)) / p  # sum_k |sin(2 pi k / p)| = cot(pi / 2p), p odd
    peak = math.cos(math.pi / 50)  # sample nearest the crest: sin(2 pi 6 / 25)
    q3 = math.sin(2 * math.pi * 3 / 25)  # 7th largest of the 25 distinct values (index 55.5 of 75)
    m4 = (2 - 2 * math.cos(w)) ** 2 * (N / 2 - math.sin(w) ** 2) / N
    f1 = 4 * math.sin(w / 2) ** 2 * (N / 2 - math.cos(w / 2) ** 2) / N
    exp = {
        "acc_x__mean": 0.0,
        "acc_x__mean_abs": mean_abs,
        "acc_x__var": 0.5,
        "acc_x__mode": -1.0,  # bins +-1.0 hold 9 samples each (values 0.998, 0.982, 0.951); tie -> smaller
        "acc_x__max": peak,
        "acc_x__min": -peak,
        "acc_x__iqr": 2 * q3,
        "acc_x__q3": q3,
        "acc_xy__corr": -1.0,
        "acc_xz__corr": 0.0,  # sin and cos are orthogonal over full periods
        "acc_yz__corr": 0.0,
        "acc_x__skew": 0.0,
        "acc_x__kurt": -1.5,  # E sin^4 / (E sin^2)^2 - 3 = (3/8) / (1/4) - 3
        "acc_x__mad": mean_abs,
        "acc_x__m4": m4,
        "acc_x__f1": f1,
        "acc_y__mean": 0.0,
        "acc_y__mean_abs": 2 * mean_abs,
        "acc_y__var": 2.0,
        "acc_y__max": 2 * peak,
        "acc_y__iqr": 4 * q3,
        "acc_y__kurt": -1.5,
        "acc_y__mad": 2 * mean_abs,
        "acc_y__m4": 4 * m4,
        "acc_z__mean": G,
        "acc_z__var": 0.125,
        "acc_z__max": G + 0.5,
        "acc_z__min": G - 0.5 * math.cos(math.pi / 25),  # cos(2 pi 12 / 25)
        "acc_z__kurt": -1.5,
    }
    _check(_one(acc), exp)


def test_catalogue_order_and_numbers():
    assert [s.number for s in CATALOGUE] == list(range(1, 53))
    assert NAMES[:4] == ["acc_x__mean", "acc_y__mean", "acc_z__mean", "acc_mag__mean"]
    assert NAMES[28:35] == ["acc_x__q3", "acc_y__q3", "acc_z__q3", "acc_mag__q3", "acc_xy__corr", "acc_xz__corr", "acc_yz__corr"]
    assert NAMES[47:] == ["acc_x__m4", "acc_y__m4", "acc_z__m4", "acc_mag__m4", "acc_x__f1"]
