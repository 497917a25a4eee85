"""Stride segmentation between consecutive zero-velocity intervals."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.zupt._intervals import intervals_table

__all__ = ["segment_strides", "label_strides"]


def segment_strides(zupts, sampling_rate_hz: float | None = None, *, max_stride_s: float | None = None) -> pd.DataFrame:
    """Strides between consecutive zero-velocity intervals, one row per stride.

    Stride k runs from the middle of zero-velocity interval k to the middle of
    interval k + 1 (mid-stance to mid-stance, the convention of gaitmap's
    ``min_vel`` strides), so every stride holds one swing and the two stance
    halves around it.

    Parameters
    ----------
    zupts : DataFrame or bool ndarray
        An interval table (``start``, ``end`` exclusive) or a per-sample mask.
    sampling_rate_hz : float, optional
        Needed for a mask; for a table, taken from ``attrs['sampling_rate_hz']``
        when not given.
    max_stride_s : float, optional
        Drop strides longer than this (e.g. across a pause); default keep all.

    Returns
    -------
    DataFrame
        ``start``, ``end`` (exclusive; samples), ``stance_start``, ``stance_end``
        (the zero-velocity interval the stride starts in), ``swing_start``,
        ``swing_end`` (the moving part: from the end of interval k to the start of
        interval k + 1), ``next_stance_start``, ``next_stance_end``, ``t_start_s``,
        ``t_end_s``, ``duration_s``. Cut training data with ``[start, end)``; label
        samples inside ``[stance_start, stance_end)`` as stance.
    """
    if isinstance(zupts, pd.DataFrame):
        if not {"start", "end"} <= set(zupts.columns):
            raise InputError(f"the interval table needs 'start' and 'end' columns, got {list(zupts.columns)}.")
        fs = sampling_rate_hz if sampling_rate_hz is not None else zupts.attrs.get("sampling_rate_hz")
        table = zupts
    else:
        fs = sampling_rate_hz
        if fs is None:
            raise InputError("segment_strides needs `sampling_rate_hz` with a per-sample mask; pass it or give the interval table.")
        table = intervals_table(np.asarray(zupts, dtype=bool), fs)
    if fs is None or not float(fs) > 0:
        raise InputError(f"`sampling_rate_hz` must be a positive number, got {fs!r}.")
    fs = float(fs)
    s = np.asarray(table["start"], dtype=np.int64)
    e = np.asarray(table["end"], dtype=np.int64)
    mid = (s + e) // 2
    out = pd.DataFrame(
        {
            "start": mid[:-1],
            "end": mid[1:],
            "stance_start": s[:-1],
            "stance_end": e[:-1],
            "swing_start": e[:-1],
            "swing_end": s[1:],
            "next_stance_start": s[1:],
            "next_stance_end": e[1:],
        }
    )
    out["t_start_s"] = out["start"] / fs
    out["t_end_s"] = out["end"] / fs
    out["duration_s"] = (out["end"] - out["start"]) / fs
    if max_stride_s is not None:
        out = out[out["duration_s"] <= max_stride_s].reset_index(drop=True)
    out.attrs["sampling_rate_hz"] = fs
    return out


def label_strides(strides: pd.DataFrame, n_samples: int) -> np.ndarray:
    """Per-sample stride index (``-1`` outside every stride) for labelling training data."""
    lab = np.full(int(n_samples), -1, dtype=np.int64)
    s = np.clip(np.asarray(strides["start"], dtype=np.int64), 0, n_samples)
    e = np.clip(np.asarray(strides["end"], dtype=np.int64), 0, n_samples)
    lengths = np.maximum(e - s, 0)
    total = int(lengths.sum())
    if total:
        offsets = np.cumsum(lengths) - lengths
        pos = np.arange(total) + np.repeat(s - offsets, lengths)
        lab[pos] = np.repeat(np.arange(len(s)), lengths)
    return lab
