"""The ``adaptive`` step detector as it was before issue 13 (gaitml 0.x, commit ba48f30): the reference.

Kept verbatim (core functions only) so that the benchmark (``benchmarks/steps.py``)
can time the reworked detector against it in the same process and the tests can
compare the two. Not part of the package: tuned on all three Oxford optimisation
users (in-sample), it counts strides in back pockets on other recordings of the
same study (issue 13).
"""

from __future__ import annotations

import numpy as np
import scipy.signal

from gaitml.errors import InputError
from gaitml.signal import bandpass, sliding_windows

__all__ = ["local_step_period", "adaptive_steps", "adaptive_step_peaks"]

BAND_HZ = (0.5, 3.0)
WINDOW_S = 4.0
HOP_S = 1.0
MIN_PERIOD_S = 0.3
MAX_PERIOD_S = 0.8
HALF_LAG_RATIO = 0.5
PROMINENCE_RATIO = 0.25
RMS_WINDOW_S = 2.0
MIN_CORRELATION = 0.2
MIN_RMS_MS2 = 0.2
MIN_DISTANCE_RATIO = 0.6
CANDIDATE_DISTANCE_S = 0.25
#: the cadence autocorrelation runs at about this rate (decimated band-limited signal)
CADENCE_RATE_HZ = 25.0


def local_step_period(
    y: np.ndarray,
    sampling_rate_hz: float,
    *,
    window_s: float = WINDOW_S,
    hop_s: float = HOP_S,
    min_period_s: float = MIN_PERIOD_S,
    max_period_s: float = MAX_PERIOD_S,
    half_lag_ratio: float = HALF_LAG_RATIO,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step period per sliding window from the normalised autocorrelation.

    Returns
    -------
    centres : int array (n_windows,)  window centre samples
    period_s : float array            step period of each window
    correlation : float array         autocorrelation at that period
    """
    fs = float(sampling_rate_hz)
    n = len(y)
    L = min(n, int(round(window_s * fs)))
    H = max(1, int(round(hop_s * fs)))
    lo = max(1, int(round(min_period_s * fs)))
    hi = int(round(max_period_s * fs))
    if hi + 2 >= L:
        raise InputError(
            f"the recording is too short for the adaptive cadence estimate: {n} samples ({n / fs:.2f} s); "
            f"it needs more than {(hi + 2) / fs:.2f} s (max_period_s={max_period_s}); use a longer recording."
        )
    w = sliding_windows(np.asarray(y, dtype=float), L, H)
    starts = np.arange(w.shape[0]) * H
    w = w - w.mean(axis=1, keepdims=True)
    # direct autocorrelation at the lags needed only (lo - 1 .. hi + 1): cheaper than an FFT of every window
    r = np.zeros((w.shape[0], hi + 2))
    r0 = np.einsum("ij,ij->i", w, w)
    for lag in range(max(1, lo - 1), hi + 2):
        r[:, lag] = np.einsum("ij,ij->i", w[:, : L - lag], w[:, lag:])
    r[:, 0] = r0
    r = np.divide(r, r0[:, None], out=np.zeros_like(r), where=r0[:, None] > 0)
    rows = np.arange(len(r))
    lags = np.arange(lo, hi + 1)
    j = np.argmax(r[:, lo : hi + 1], axis=1)
    lag = lags[j]
    best = r[rows, lag]
    # stride or step: a local maximum near half the lag, strong enough, makes the half lag the step period
    half = lag // 2
    a = np.maximum(lo, np.floor(0.85 * half)).astype(int)
    b = np.floor(1.15 * half).astype(int) + 1
    inside = (lags[None, :] >= a[:, None]) & (lags[None, :] < b[:, None])
    rl = np.where(inside, r[:, lo : hi + 1], -np.inf)
    j2 = np.argmax(rl, axis=1) + lo
    r2 = r[rows, j2]
    is_max = (r2 >= r[rows, j2 - 1]) & (r2 >= r[rows, j2 + 1])
    use_half = inside.any(axis=1) & (half >= lo) & is_max & (r2 > half_lag_ratio * best)
    lag = np.where(use_half, j2, lag)
    best = np.where(use_half, r2, best)
    return starts + L // 2, lag / fs, best


def adaptive_steps(
    acc_mag_ms2: np.ndarray,
    sampling_rate_hz: float,
    *,
    band_hz: tuple[float, float] = BAND_HZ,
    window_s: float = WINDOW_S,
    hop_s: float = HOP_S,
    min_period_s: float = MIN_PERIOD_S,
    max_period_s: float = MAX_PERIOD_S,
    half_lag_ratio: float = HALF_LAG_RATIO,
    prominence_ratio: float = PROMINENCE_RATIO,
    rms_window_s: float = RMS_WINDOW_S,
    min_correlation: float = MIN_CORRELATION,
    min_rms_ms2: float = MIN_RMS_MS2,
    min_distance_ratio: float = MIN_DISTANCE_RATIO,
) -> dict[str, np.ndarray]:
    """Detect steps in |acc| (m/s^2); returns ``peak`` samples, the band-passed ``y``, and the local ``period_s`` and ``correlation`` at each peak."""
    x = np.asarray(acc_mag_ms2, dtype=float)
    fs = float(sampling_rate_hz)
    n = len(x)
    y = bandpass(x - np.median(x), band_hz[0], band_hz[1], fs, order=2)
    # the cadence estimate runs on the band-limited signal decimated to about CADENCE_RATE_HZ
    q = max(1, int(fs // CADENCE_RATE_HZ))
    centres, per, corr = local_step_period(
        y[::q], fs / q, window_s=window_s, hop_s=hop_s, min_period_s=min_period_s, max_period_s=max_period_s, half_lag_ratio=half_lag_ratio
    )
    centres = centres * q
    pk, props = scipy.signal.find_peaks(y, distance=max(1, int(round(CANDIDATE_DISTANCE_S * fs))), prominence=0)
    T = np.interp(pk, centres, per)
    R = np.interp(pk, centres, corr)
    # local RMS over rms_window_s centred on each candidate (cumulative sum, shrunk at the edges)
    c = np.concatenate([[0.0], np.cumsum(y * y)])
    w = max(1, int(round(rms_window_s * fs)))
    lo_i = np.maximum(pk - w // 2, 0)
    hi_i = np.minimum(pk - w // 2 + w, n)
    rms = np.sqrt((c[hi_i] - c[lo_i]) / (hi_i - lo_i))
    keep = (props["prominences"] >= prominence_ratio * rms) & (R >= min_correlation) & (rms >= min_rms_ms2)
    pk, T = pk[keep], T[keep]
    min_gap = (min_distance_ratio * T * fs).tolist()
    yv = y[pk].tolist()
    out: list[int] = []
    hv: list[float] = []
    for p, g, v in zip(pk.tolist(), min_gap, yv, strict=True):
        if out and p - out[-1] < g:
            if v > hv[-1]:
                out[-1], hv[-1] = p, v
            continue
        out.append(p)
        hv.append(v)
    peaks = np.asarray(out, dtype=np.int64)
    return {"peak": peaks, "y": y, "period_s": np.interp(peaks, centres, per), "correlation": np.interp(peaks, centres, corr)}


def adaptive_step_peaks(acc_mag_ms2: np.ndarray, sampling_rate_hz: float) -> np.ndarray:
    """Step peak samples of the old detector with its defaults."""
    return adaptive_steps(acc_mag_ms2, sampling_rate_hz)["peak"]
