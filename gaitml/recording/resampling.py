"""Resampling timestamped samples onto a uniform grid."""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml.errors import InputError

__all__ = ["resample_uniform"]

#: Resampling never makes more than this many times the original samples (+1000):
#: up-sampling further adds no information and could exhaust memory.
_MAX_UPSAMPLE = 100.0


def resample_uniform(
    t_s: np.ndarray,
    acc: np.ndarray,
    sampling_rate_hz: float,
    *,
    gyr: np.ndarray | None = None,
    labels: Any = None,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Linearly interpolate samples at increasing times ``t_s`` onto a uniform grid.

    The grid is ``t_s[0] + k / sampling_rate_hz`` for every k whose time does
    not pass ``t_s[-1]``. Labels are carried by the latest original sample at or
    before each grid time (sample-and-hold: labels cannot be interpolated).

    Returns
    -------
    acc, gyr, labels : resampled arrays (gyr and labels None when not given).
    """
    t = np.asarray(t_s, dtype=float)
    n_float = np.floor((t[-1] - t[0]) * sampling_rate_hz + 1e-9) + 1
    if n_float > _MAX_UPSAMPLE * len(t) + 1000:
        raise InputError(
            f"resampling {len(t)} samples at {sampling_rate_hz:g} Hz would make {n_float:.4g} samples "
            f"(more than {_MAX_UPSAMPLE:g}x the original); ask for a lower --sampling-rate-hz."
        )
    n_new = int(n_float)
    grid = t[0] + np.arange(n_new) / sampling_rate_hz

    def interp(x: np.ndarray) -> np.ndarray:
        return np.column_stack([np.interp(grid, t, x[:, j]) for j in range(x.shape[1])])

    new_acc = interp(acc)
    new_gyr = None if gyr is None else interp(gyr)
    new_labels = None
    if labels is not None:
        lab = np.asarray(labels).astype(str)
        idx = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 1)
        new_labels = lab[idx]
    return new_acc, new_gyr, new_labels
