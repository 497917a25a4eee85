"""Magnitude, moving average and Butterworth filters (plain functions over arrays)."""

from __future__ import annotations

import numpy as np
import scipy.signal

from gaitml.errors import InputError

__all__ = ["magnitude", "centered_window_sums", "moving_average", "butter_filter", "lowpass", "bandpass"]


def magnitude(x: np.ndarray) -> np.ndarray:
    """Euclidean norm of each row of an (n, 3) array -> shape (n,)."""
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2:
        raise InputError(f"`x` must be 2-D (n, channels), got shape {arr.shape}.")
    return np.sqrt(np.einsum("ij,ij->i", arr, arr))


def centered_window_sums(x: np.ndarray, n_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Sums of ``x`` over the centred window of ``n_samples`` around each sample (axis 0), and the window counts.

    The window of sample i is ``[i - n // 2, i + n - 1 - n // 2]`` (for even ``n`` it
    reaches one more sample into the past), shrunk at the edges to the samples that
    exist. One cumulative sum padded on both sides, read with two plain slices (O(n),
    no gather): the single centred-window primitive of the package (moving averages,
    the zero-velocity detectors' window statistics).

    Returns
    -------
    sums : ndarray, same shape as ``x``
    counts : ndarray (n,) of int
    """
    arr = np.asarray(x, dtype=float)
    n = int(n_samples)
    if n < 1:
        raise InputError(f"`n_samples` must be >= 1, got {n_samples}.")
    m = arr.shape[0]
    back = n // 2
    fwd = n - 1 - back
    c = np.empty((m + n,) + arr.shape[1:])
    # c[back + j] = sum of the first j samples (j = 0..m); constant beyond both ends
    c[: back + 1] = 0.0
    np.cumsum(arr, axis=0, out=c[back + 1 : back + 1 + m])
    c[back + 1 + m :] = c[back + m]
    sums = c[n:] - c[:m]
    if m > n:  # full windows inside; only the edges are shrunk
        counts = np.full(m, n, dtype=np.int64)
        counts[:back] = np.arange(back) + fwd + 1
        counts[m - fwd :] = m - (np.arange(m - fwd, m) - back)
    else:
        idx = np.arange(m)
        counts = np.minimum(idx + fwd + 1, m) - np.maximum(idx - back, 0)
    return sums, counts


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
    if mode == "centered":
        sums, counts = centered_window_sums(arr, n)
        m, back = arr.shape[0], n // 2
        fwd = n - 1 - back
        if m <= n:
            return sums / counts.reshape((-1,) + (1,) * (arr.ndim - 1))
        out = sums / n  # full windows; then the shrunk edge windows
        for sl in (slice(0, back), slice(m - fwd, m)):
            out[sl] = sums[sl] / counts[sl].reshape((-1,) + (1,) * (arr.ndim - 1))
        return out
    if mode != "causal":
        raise InputError(f"`mode` must be 'centered' or 'causal', got {mode!r}.")
    c = np.cumsum(np.concatenate([np.zeros((1,) + arr.shape[1:]), arr], axis=0), axis=0)
    idx = np.arange(arr.shape[0])
    lo = np.maximum(idx - n + 1, 0)
    hi = idx + 1
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
