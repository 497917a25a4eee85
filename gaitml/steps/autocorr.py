"""Autocorrelation step counting, the second baseline of paper 000.

Paper 000 (Bi et al. 2021) compares IFSM with the autocorrelation pedometer of
Chen, Zhang and Yang (its ref. [14], J. Chinese Inertial Technology 2014): the
normalised autocorrelation of the acceleration magnitude over a fixed window
tells whether the person walks (a strong periodic peak) and gives the step
period (the lag of the first dominant peak); the window then holds
``window / period`` steps. Paper 000 notes such methods need a long fixed
window and react slowly to speed changes.

Our definition (parameters are ours; paper 000 prints none): |acc| smoothed by
a 5-sample moving average at 50 Hz (0.1 s), non-overlapping windows of
``window_s``; in each window the demeaned signal's normalised autocorrelation
``r(tau) = sum x_i x_{i+tau} / sum x_i^2`` over lags ``min_period_s ..
max_period_s``; the first local maximum whose value reaches
``dominance * max r`` is the step period, and the window counts as walking
when that peak's ``r`` is at least ``min_correlation`` (and the signal's
standard deviation at least ``min_std_ms2``). Step events: the step phase
``integral of 1 / period dt`` is accumulated sample by sample over walking
windows and a step is emitted each time it passes an integer.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import NON_NEGATIVE, POSITIVE
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import moving_average
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import acc_magnitude, as_recording, check_positive
from gaitml.steps._table import make_step_table

__all__ = ["RATE_FLOOR_HZ", "AutocorrStepDetector", "window_step_periods", "autocorr_steps"]

WINDOW_S = 2.0  #: our choice: fixed analysis window (s)
MIN_PERIOD_S = 0.3  #: our choice: shortest step period searched (s), 3.3 steps/s
MAX_PERIOD_S = 1.0  #: our choice: longest step period searched (s), 1 step/s
MIN_CORRELATION = 0.3  #: our choice: normalised autocorrelation of a walking window
DOMINANCE = 0.7  #: our choice: "dominant" = at least this fraction of the largest peak in range
MIN_STD_MS2 = 0.5  #: our choice: a still window has less variation than this
SMOOTHING_S = 0.1  #: paper 000 sec. 2.1: 5 samples at 50 Hz


def window_step_periods(
    x: np.ndarray,
    fs: float,
    *,
    window_samples: int,
    min_lag: int,
    max_lag: int,
    min_correlation: float,
    dominance: float,
    min_std: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Step period (samples, 0 = not walking) and peak correlation of each full window of ``x``.

    All windows at once: FFT autocorrelation of the (n_windows, L) block.
    """
    L = int(window_samples)
    nw = len(x) // L
    if nw == 0:
        return np.zeros(0), np.zeros(0)
    w = x[: nw * L].reshape(nw, L)
    w = w - w.mean(axis=1, keepdims=True)
    nfft = 1 << int(np.ceil(np.log2(2 * L)))
    F = np.fft.rfft(w, nfft, axis=1)
    r = np.fft.irfft(F * np.conj(F), nfft, axis=1)[:, : max_lag + 2]
    r0 = r[:, :1]
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.where(r0 > 0, r / r0, 0.0)
    seg = r[:, min_lag : max_lag + 1]
    left = r[:, min_lag - 1 : max_lag]
    right = r[:, min_lag + 1 : max_lag + 2]
    is_peak = (seg > left) & (seg >= right)
    best = np.where(is_peak, seg, -np.inf).max(axis=1)
    dom = is_peak & (seg >= dominance * best[:, None]) & (seg > 0)
    has = dom.any(axis=1)
    first = np.argmax(dom, axis=1)
    lag = (first + min_lag).astype(float)
    rpk = np.where(has, seg[np.arange(nw), first], 0.0)
    walking = has & (rpk >= min_correlation) & (w.std(axis=1) >= min_std)
    return np.where(walking, lag, 0.0), rpk


def autocorr_steps(period_samples_per_window: np.ndarray, window_samples: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Step completion samples and periods from per-window periods (phase accumulation)."""
    per = np.repeat(period_samples_per_window, window_samples)
    per = np.concatenate([per, np.zeros(n - len(per))])
    rate = np.where(per > 0, 1.0 / np.where(per > 0, per, 1.0), 0.0)
    phase = np.cumsum(rate)
    ends = np.flatnonzero(np.floor(phase[1:]) > np.floor(phase[:-1])) + 1
    if len(phase) and phase[0] >= 1:
        ends = np.concatenate([[0], ends])
    return ends.astype(np.int64), per[ends]


#: lowest recording rate (Hz) autocorr's count holds at (paper 000 records at 50 Hz): the floor rule of
#: :mod:`gaitml.steps._rate` on tyrex (the figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 30.0


class AutocorrStepDetector(BaseStepDetector):
    """Autocorrelation step counter (paper 000's baseline, its ref. [14]).

    Parameters
    ----------
    window_s : float, default 2.0
        Fixed analysis window (s), ours.
    min_period_s, max_period_s : float, default 0.3 / 1.0
        Step periods searched (s), ours.
    min_correlation : float, default 0.3
        Normalised autocorrelation a walking window reaches, ours.
    dominance : float, default 0.7
        A "dominant" peak reaches this fraction of the largest one in range, ours.
    min_std_ms2 : float, default 0.5
        A still window has a smaller standard deviation of |acc| (m/s^2), ours.
    smoothing_s : float, default 0.1
        Moving average of |acc| (paper 000 sec. 2.1: 5 samples at 50 Hz).

    Attributes
    ----------
    steps_ : DataFrame
        One row per emitted step: ``end`` the sample where the step phase
        passes an integer, ``start = end - period``, ``peak`` = ``end``,
        ``period_s`` the window's autocorrelation period, ``correlation``.
        ``attrs['event'] = 't_end_s'``.
    windows_ : DataFrame
        ``start``, ``end``, ``period_s`` (0 = not walking), ``correlation``.

    References
    ----------
    Bi J. et al. 2021 (paper 000), sec. 1 and Table 2; Chen G., Zhang Y., Yang Z.,
    Realization of Pedometer with Auto-correlation Analysis Based on Mobile Phone
    Sensor, J. Chinese Inertial Technology 2014.
    """

    name = "autocorr"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "window_s": [POSITIVE],
        "min_period_s": [POSITIVE],
        "max_period_s": [POSITIVE],
        "smoothing_s": [POSITIVE],
        "min_std_ms2": [NON_NEGATIVE],
    }

    def __init__(
        self,
        *,
        window_s: float = WINDOW_S,
        min_period_s: float = MIN_PERIOD_S,
        max_period_s: float = MAX_PERIOD_S,
        min_correlation: float = MIN_CORRELATION,
        dominance: float = DOMINANCE,
        min_std_ms2: float = MIN_STD_MS2,
        smoothing_s: float = SMOOTHING_S,
    ):
        self.window_s = window_s
        self.min_period_s = min_period_s
        self.max_period_s = max_period_s
        self.min_correlation = min_correlation
        self.dominance = dominance
        self.min_std_ms2 = min_std_ms2
        self.smoothing_s = smoothing_s

    def detect(self, recording: Recording) -> AutocorrStepDetector:
        """Detect steps in ``recording``; results in ``steps_`` and ``windows_``."""
        self._validate_params()
        rec = as_recording(recording, "autocorr step detection", min_duration_s=float(self.window_s))
        fs = rec.sampling_rate_hz
        check_positive("window_s", self.window_s)
        lo = int(round(check_positive("min_period_s", self.min_period_s) * fs))
        hi = int(round(check_positive("max_period_s", self.max_period_s) * fs))
        L = int(round(self.window_s * fs))
        if lo < 1 or hi <= lo or hi + 2 > L:
            raise InputError(
                f"need 1 <= min_period_s * fs < max_period_s * fs < window_s * fs - 2, got {lo}, {hi}, {L} samples; "
                "choose a window longer than the longest period."
            )
        x = moving_average(acc_magnitude(rec), max(1, int(round(self.smoothing_s * fs))))
        per, rpk = window_step_periods(
            x,
            fs,
            window_samples=L,
            min_lag=lo,
            max_lag=hi,
            min_correlation=float(self.min_correlation),
            dominance=float(self.dominance),
            min_std=float(self.min_std_ms2),
        )
        ends, p = autocorr_steps(per, L, rec.n_samples)
        start = np.maximum(ends - p.astype(np.int64), 0)
        corr = np.repeat(rpk, L)
        corr = np.concatenate([corr, np.zeros(rec.n_samples - len(corr))])[ends]
        self.steps_: pd.DataFrame = make_step_table(start, ends, ends, fs, event="t_end_s", period_s=p / fs, correlation=corr)
        ws = np.arange(len(per)) * L
        self.windows_ = pd.DataFrame({"start": ws, "end": ws + L, "period_s": per / fs, "correlation": rpk})
        return self
