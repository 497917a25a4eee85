"""gaitml.signal: known answers and no-copy windows."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml import InputError
from gaitml import signal as gs


def test_magnitude():
    x = np.array([[3.0, 4.0, 0.0], [1.0, 2.0, 2.0]])
    np.testing.assert_allclose(gs.magnitude(x), [5.0, 3.0])


def test_moving_average_centered_and_causal():
    x = np.arange(10, dtype=float)
    c = gs.moving_average(x, 3)
    np.testing.assert_allclose(c[1:-1], x[1:-1])  # a ramp is its own centred mean
    assert c[0] == pytest.approx(0.5) and c[-1] == pytest.approx(8.5)
    k = gs.moving_average(x, 3, mode="causal")
    np.testing.assert_allclose(k[2:], x[2:] - 1)
    np.testing.assert_allclose(gs.moving_average(np.full(7, 4.2), 5), 4.2)
    np.testing.assert_allclose(gs.moving_average(np.ones((6, 3)), 4), 1.0)
    with pytest.raises(InputError, match="n_samples"):
        gs.moving_average(x, 0)


def test_butterworth_lowpass_keeps_slow_removes_fast():
    fs = 100.0
    t = np.arange(2000) / fs
    slow = np.sin(2 * np.pi * 1.0 * t)
    fast = 0.5 * np.sin(2 * np.pi * 20.0 * t)
    y = gs.lowpass(slow + fast, 4.0, fs)
    assert np.max(np.abs(y[200:-200] - slow[200:-200])) < 0.02  # zero phase: no delay
    yc = gs.lowpass(slow + fast, 4.0, fs, zero_phase=False)
    lag = np.argmax(np.correlate(yc[500:1500], slow[500:1500], "full")) - 999
    assert lag >= 0  # causal filter delays
    with pytest.raises(InputError, match="Nyquist"):
        gs.lowpass(slow, 60.0, fs)
    with pytest.raises(InputError, match="too short"):
        gs.lowpass(slow[:10], 4.0, fs)


def test_bandpass_passes_band():
    fs = 50.0
    t = np.arange(5000) / fs
    x = np.sin(2 * np.pi * 2.0 * t) + 3.0
    y = gs.bandpass(x, 0.5, 5.0, fs)
    assert abs(y[500:-500].mean()) < 0.01
    assert np.std(y[500:-500]) == pytest.approx(np.sqrt(0.5), rel=0.05)


def test_sliding_windows_is_a_view():
    x = np.arange(30, dtype=float).reshape(10, 3)
    w = gs.sliding_windows(x, 4, 2)
    assert w.shape == (4, 4, 3)
    assert np.shares_memory(w, x)
    np.testing.assert_array_equal(w[1], x[2:6])
    w1 = gs.sliding_windows(np.arange(10.0), 5, 5)
    assert w1.shape == (2, 5)
    with pytest.raises(InputError, match="fewer than one window"):
        gs.sliding_windows(x, 11)


def test_window_params():
    assert gs.window_params(1.5, 0.5, 50.0) == (75, 38)
    with pytest.raises(InputError, match="overlap"):
        gs.window_params(1.5, 1.0, 50.0)
    with pytest.raises(InputError, match="shorter than 2 samples"):
        gs.window_params(0.01, 0.5, 50.0)


def test_gravity_direction_and_tilt():
    acc = np.tile([0.0, 0.0, 9.81], (100, 1))
    np.testing.assert_allclose(gs.gravity_direction(acc), [0, 0, 1])
    roll, pitch = gs.tilt_angles(np.array([0.0, 0.0, 1.0]))
    assert roll == pytest.approx(0) and pitch == pytest.approx(0)
    # phone pitched up by 30 degrees about x: gravity appears partly on +y
    g = np.array([0.0, np.sin(np.pi / 6), np.cos(np.pi / 6)])
    roll, pitch = gs.tilt_angles(g)
    assert pitch == pytest.approx(np.pi / 6)
    v, h = gs.gravity_components(acc + [1.0, 0, 0], np.array([0, 0, 1.0]))
    np.testing.assert_allclose(v, 9.81)
    np.testing.assert_allclose(h[:, 0], 1.0)
    per_sample = gs.gravity_direction(acc + 0.01, 100.0)
    assert per_sample.shape == (100, 3)
