"""Magnitude, moving average and Butterworth filters (plain functions over arrays)."""

from __future__ import annotations

import numpy as np
import scipy.signal

from gaitml.errors import InputError

__all__ = ["magnitude", "moving_average", "butter_filter", "lowpass", "bandpass"]


def magnitude(x: np.ndarray) -> np.ndarray:
    """Euclidean norm of each row of an (n, 3) array -> shape (n,)."""
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2:
        raise InputError(f"`x` must be 2-D (n, channels), got shape {arr.shape}.")
    return np.sqrt(np.einsum("ij,ij->i", arr, arr))


def moving_average(x: np.ndarray, n_samples: int, *, mode: str = "centered") -> np.ndarray:
    """Moving average over ``n_samples`` along axis 0, same length as ``x``.

    ``mode='centered'``: the mean of the window centred on each sample (for even
    ``n_samples`` the window reaches one more sample into the past); at the edges
    the window is shrunk to the samples that exist (no zero padding, so a
    constant stays constant). ``mode='causal'``: the mean of the current and the
    ``n_samples - 1`` previous samples (shrunk at the start), as a streaming
    implementation would compute it.

    Papers 003 (N = 3) and 000 (N = 5) smooth the acceleration magnitude this way.
    """
    arr = np.asarray(x, dtype=float)
    n = int(n_samples)
    if n < 1:
        raise InputError(f"`n_samples` must be >= 1, got {n_samples}.")
    if n == 1 or arr.shape[0] == 0:
        return arr.copy()
    c = np.cumsum(np.concatenate([np.zeros((1,) + arr.shape[1:]), arr], axis=0), axis=0)
    m = arr.shape[0]
    idx = np.arange(m)
    if mode == "causal":
        lo = np.maximum(idx - n + 1, 0)
        hi = idx + 1
    elif mode == "centered":
        back = n // 2
        fwd = n - 1 - back
        lo = np.maximum(idx - back, 0)
        hi = np.minimum(idx + fwd + 1, m)
    else:
        raise InputError(f"`mode` must be 'centered' or 'causal', got {mode!r}.")
    cnt = (hi - lo).reshape((-1,) + (1,) * (arr.ndim - 1))
    return (c[hi] - c[lo]) / cnt


def butter_filter(
    x: np.ndarray,
    cutoff_hz: float | tuple[float, float],
    sampling_rate_hz: float,
    *,
    order: int = 4,
    btype: str = "lowpass",
    zero_phase: bool = True,
) -> np.ndarray:
    """Butterworth filter along axis 0 in second-order sections.

    ``zero_phase=True`` runs it forwards and backwards (``sosfiltfilt``: no delay,
    squared magnitude response, offline only); ``zero_phase=False`` is the causal
    filter a streaming device would run (``sosfilt``, with its group delay).
    """
    arr = np.asarray(x, dtype=float)
    nyq = sampling_rate_hz / 2.0
    cuts = np.atleast_1d(np.asarray(cutoff_hz, dtype=float))
    if np.any(cuts <= 0) or np.any(cuts >= nyq):
        raise InputError(
            f"`cutoff_hz`={cutoff_hz} must lie strictly between 0 and the Nyquist frequency "
            f"{nyq:g} Hz (`sampling_rate_hz`={sampling_rate_hz:g}); choose a lower cut-off or a higher rate."
        )
    sos = scipy.signal.butter(order, cuts if cuts.size > 1 else cuts[0], btype=btype, fs=sampling_rate_hz, output="sos")
    if zero_phase:
        padlen = 3 * (2 * len(sos) + 1)
        if arr.shape[0] <= padlen:
            raise InputError(
                f"the signal is too short for a zero-phase order-{order} filter: {arr.shape[0]} samples "
                f"<= {padlen}; use a longer recording or zero_phase=False."
            )
        return scipy.signal.sosfiltfilt(sos, arr, axis=0)
    zi = scipy.signal.sosfilt_zi(sos)
    zi = zi.reshape(zi.shape + (1,) * (arr.ndim - 1)) * arr[:1]
    out, _ = scipy.signal.sosfilt(sos, arr, axis=0, zi=zi)
    return out


def lowpass(x, cutoff_hz, sampling_rate_hz, *, order=4, zero_phase=True):
    """Low-pass Butterworth filter (see :func:`butter_filter`)."""
    return butter_filter(x, cutoff_hz, sampling_rate_hz, order=order, btype="lowpass", zero_phase=zero_phase)


def bandpass(x, low_hz, high_hz, sampling_rate_hz, *, order=2, zero_phase=True):
    """Band-pass Butterworth filter (see :func:`butter_filter`)."""
    return butter_filter(x, (low_hz, high_hz), sampling_rate_hz, order=order, btype="bandpass", zero_phase=zero_phase)
