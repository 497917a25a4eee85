"""Sliding windows as strided views (no copies)."""

from __future__ import annotations

import numpy as np

from gaitml.errors import InputError

__all__ = ["sliding_windows", "window_starts", "window_params"]


def window_params(length_s: float, overlap: float, sampling_rate_hz: float) -> tuple[int, int]:
    """Convert a window length in s and an overlap fraction to (length, hop) in samples.

    ``overlap`` is the shared fraction of consecutive windows, in [0, 1).
    """
    if not (np.isfinite(length_s) and length_s > 0):
        raise InputError(f"the window length must be a positive number of seconds, got {length_s!r}; e.g. 1.5.")
    if not 0 <= overlap < 1:
        raise InputError(f"`overlap` must be in [0, 1), got {overlap}; e.g. 0.5 for half-overlapping windows.")
    length = int(round(length_s * sampling_rate_hz))
    if length < 2:
        raise InputError(
            f"the window is shorter than 2 samples (`length_s`={length_s}, `sampling_rate_hz`={sampling_rate_hz}); specify a longer window."
        )
    hop = max(1, int(round(length * (1 - overlap))))
    return length, hop


def window_starts(n_samples: int, length: int, hop: int) -> np.ndarray:
    """Start indices of all complete windows of ``length`` samples every ``hop`` samples."""
    if n_samples < length:
        return np.zeros(0, dtype=np.int64)
    return np.arange(0, n_samples - length + 1, hop, dtype=np.int64)


def sliding_windows(x: np.ndarray, length: int, hop: int = 1) -> np.ndarray:
    """Read-only strided view of all complete windows along axis 0.

    Parameters
    ----------
    x : ndarray, shape (n, ...)
    length, hop : int
        Window length and step, in samples.

    Returns
    -------
    ndarray, shape (n_windows, length, ...)
        A view into ``x`` (no data copied); window i is ``x[i*hop : i*hop+length]``.
    """
    arr = np.asarray(x)
    if length < 1 or hop < 1:
        raise InputError(f"window `length` and `hop` must be >= 1, got {length} and {hop}.")
    if arr.shape[0] < length:
        raise InputError(
            f"the signal has {arr.shape[0]} samples, fewer than one window of {length}; use a longer recording or a shorter window."
        )
    v = np.lib.stride_tricks.sliding_window_view(arr, length, axis=0)[::hop]
    # sliding_window_view puts the window axis last; move it to position 1.
    return np.moveaxis(v, -1, 1) if arr.ndim > 1 else v
