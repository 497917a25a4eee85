"""Step length models (paper 003 sec. 4.1)."""

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.pdr.step_length import StepLengthModel, linear_step_length, step_length_features, weinberg_step_length


def _features(n, rng):
    return pd.DataFrame(
        {
            "freq_hz": rng.uniform(1.4, 2.4, n),
            "var_ms2sq": rng.uniform(2.0, 12.0, n),
            "a_max_ms2": rng.uniform(8.0, 20.0, n),
            "a_min_ms2": rng.uniform(-8.0, -2.0, n),
        }
    )


def test_known_answers():
    assert linear_step_length(2.0, 4.0, 0.1, 0.2, 0.05) == pytest.approx(0.1 + 0.4 + 0.2)
    assert weinberg_step_length(18.0, 2.0, 0.5) == pytest.approx(0.5 * 16**0.25)


def test_fit_recovers_linear_and_weinberg_coefficients():
    rng = np.random.default_rng(0)
    f = _features(400, rng)
    modes = rng.choice(["walk", "run", "backward", "side_left"], 400)
    true = {"walk": (0.3, 0.2, 0.01), "backward": (0.1, 0.15, 0.005), "side_left": (0.05, 0.12, 0.02)}
    L = np.empty(400)
    for m, (a, b, c) in true.items():
        s = modes == m
        L[s] = linear_step_length(f.freq_hz[s], f.var_ms2sq[s], a, b, c)
    s = modes == "run"
    L[s] = weinberg_step_length(f.a_max_ms2[s], f.a_min_ms2[s], 0.52)
    model = StepLengthModel().fit(f, L + rng.normal(0, 1e-4, 400), modes)
    for m, coef in true.items():
        assert model.coefficients_[m][0] == "linear"
        assert np.allclose(model.coefficients_[m][1], coef, atol=5e-3)
    assert model.coefficients_["run"] == ("weinberg", pytest.approx((0.52,), abs=1e-3))
    assert np.allclose(model.predict(f, modes), L, atol=2e-3)
    assert sorted(model.fitted_modes_) == ["backward", "run", "side_left", "walk"]
    # side_right had no data: keeps its default
    assert model.coefficients_["side_right"] == StepLengthModel().coefficients_in_use()["side_right"]


def test_defaults_give_plausible_lengths():
    f = pd.DataFrame({"freq_hz": [1.8] * 5, "var_ms2sq": [5.0] * 5, "a_max_ms2": [15.0] * 5, "a_min_ms2": [-5.0] * 5})
    L = StepLengthModel().predict(f, ["walk", "run", "backward", "side_left", "side_right"])
    assert 0.6 < L[0] < 0.8 and 0.8 < L[1] < 1.2 and 0.3 < L[2] < 0.55 and 0.3 < L[3] < 0.5


def test_calibrate_from_a_walk_of_known_distance():
    rng = np.random.default_rng(1)
    f = _features(100, rng)
    modes = np.full(100, "walk")
    model = StepLengthModel().calibrate(f, modes, 77.0)
    assert model.predict(f, modes).sum() == pytest.approx(77.0)
    assert model.scale_ > 0


def test_save_load_roundtrip(tmp_path):
    model = StepLengthModel({"walk": ("linear", (0.2, 0.3, 0.01)), "run": ("weinberg", (0.6,))})
    p = model.save(tmp_path / "sl.json")
    back = StepLengthModel.load(p)
    assert back.coefficients_in_use() == model.coefficients_in_use()


def test_features_from_acc():
    fs = 50.0
    t = np.arange(200) / fs
    acc = np.zeros((200, 3))
    acc[:, 2] = 9.80665 + 3.0 * np.sin(2 * np.pi * 2.0 * t)
    steps = pd.DataFrame({"start": [0, 25, 50], "end": [25, 50, 75], "period_s": [0.5, 0.5, 0.5]})
    f = step_length_features(acc, steps, fs)
    assert np.allclose(f.freq_hz, 2.0)
    assert np.allclose(f.var_ms2sq, 4.5, rtol=0.08)  # variance of 3 sin = 4.5 (less a little for the N=3 smoothing)
    assert (f.a_max_ms2 > 2.7).all() and (f.a_min_ms2 < -2.7).all()


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: StepLengthModel({"walk": ("quadratic", (1.0,))}).predict(_features(3, np.random.default_rng(0)), ["walk"] * 3), "must be"),
        (lambda: StepLengthModel().calibrate(_features(3, np.random.default_rng(0)), ["walk"] * 3, -1.0), "positive"),
        (lambda: StepLengthModel().predict(pd.DataFrame({"x": [1]}), ["walk"]), "columns"),
        (lambda: StepLengthModel.from_dict({"format": "other"}), "not a gaitml step length model"),
    ],
)
def test_bad_inputs(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_load_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        StepLengthModel.load(tmp_path / "nope.json")
