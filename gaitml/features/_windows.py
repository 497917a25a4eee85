"""Windowing of a recording by length and overlap in seconds, with majority labels."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.signal import window_params, window_starts

__all__ = ["make_windows", "window_length_samples"]

#: Window length chosen by paper 003 sec. 3.3 (Table 2 / Fig. 6).
WINDOW_LENGTH_S = 1.5
#: Overlap of consecutive windows (our default; the paper does not state one).
WINDOW_OVERLAP = 0.5
#: Windows whose majority label covers less than this fraction are dropped.
MIN_LABEL_FRACTION = 0.5


def window_length_samples(length_s: float, overlap: float, sampling_rate_hz: float) -> tuple[int, int]:
    """(length, hop) in samples, as :func:`gaitml.signal.window_params`."""
    return window_params(length_s, overlap, sampling_rate_hz)


def _check_enough(n_samples: int, length: int, length_s: float, fs: float, name: str) -> None:
    if n_samples < length:
        raise InputError(
            f"recording '{name}' has {n_samples} samples ({n_samples / fs:.2f} s), fewer than one window of "
            f"{length} samples ({length_s:g} s at {fs:g} Hz); use a longer recording or a shorter window (--window-s)."
        )


def make_windows(
    recording, length_s: float = WINDOW_LENGTH_S, overlap: float = WINDOW_OVERLAP, *, min_label_fraction: float = MIN_LABEL_FRACTION
) -> pd.DataFrame:
    """Cut a recording into windows of ``length_s`` seconds overlapping by ``overlap``.

    Parameters
    ----------
    recording : Recording
    length_s : float
        Window length in s (paper 003 sec. 3.3 chooses 1.5 s). Converted to
        ``round(length_s * fs)`` samples by :func:`gaitml.signal.window_params`.
    overlap : float
        Shared fraction of consecutive windows in [0, 1); hop =
        ``max(1, round(length * (1 - overlap)))`` samples.
    min_label_fraction : float
        When the recording has per-sample labels, windows whose majority label
        covers less than this fraction of the window are dropped (and counted).
        0 keeps every window.

    Returns
    -------
    DataFrame
        One row per complete window (a trailing partial window is not formed):
        ``start``, ``end`` (sample indices, end exclusive), ``t_start_s``,
        ``t_end_s`` (= end / fs), and with labels ``label`` (majority; ties go
        to the label that sorts first) and ``label_fraction``. The index is
        0..n-1 after dropping. ``attrs``: ``n_total`` (windows before dropping),
        ``n_dropped``, ``length_samples``, ``hop_samples``, ``length_s``,
        ``overlap``, ``sampling_rate_hz``, ``min_label_fraction``.

    Raises
    ------
    InputError
        Bad ``overlap``/``min_label_fraction``, or a recording shorter than one window.
    """
    if not 0.0 <= float(min_label_fraction) <= 1.0:
        raise InputError(f"`min_label_fraction` must be in [0, 1], got {min_label_fraction}; e.g. 0.5 keeps windows with a clear majority.")
    fs = float(recording.sampling_rate_hz)
    length, hop = window_params(length_s, overlap, fs)
    n = recording.n_samples
    _check_enough(n, length, length_s, fs, recording.name)
    starts = window_starts(n, length, hop)
    ends = starts + length
    df = pd.DataFrame({"start": starts, "end": ends, "t_start_s": starts / fs, "t_end_s": ends / fs})
    n_total = len(df)
    if recording.labels is not None:
        uniq, codes = np.unique(np.asarray(recording.labels), return_inverse=True)
        # per class (a handful), cumulative counts: count of class k in [s, e) = C[e] - C[s]
        counts = np.empty((len(starts), len(uniq)), dtype=np.int64)
        cum = np.zeros(n + 1, dtype=np.int64)
        for k in range(len(uniq)):
            np.cumsum(codes == k, out=cum[1:])
            counts[:, k] = cum[ends] - cum[starts]
        best = np.argmax(counts, axis=1)
        df["label"] = uniq[best].astype(object)
        df["label_fraction"] = counts[np.arange(len(best)), best] / float(length)
        keep = df["label_fraction"].to_numpy() >= float(min_label_fraction)
        df = df.loc[keep].reset_index(drop=True)
    df.attrs.update(
        n_total=int(n_total),
        n_dropped=int(n_total - len(df)),
        length_samples=int(length),
        hop_samples=int(hop),
        length_s=float(length_s),
        overlap=float(overlap),
        sampling_rate_hz=fs,
        min_label_fraction=float(min_label_fraction),
    )
    return df
