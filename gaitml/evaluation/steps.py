"""Step detection metrics: count accuracy, tolerance matching, timing and period errors.

A detector's step table says which time is its step time
(``table.attrs['event']``: ``t_end_s`` for FSM detectors, ``t_peak_s`` for peak
detectors, DESIGN sec. 2); that column is matched against the true step times.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from gaitml.errors import InputError

__all__ = ["count_accuracy", "match_steps", "evaluate_steps", "step_times"]

#: default matching tolerance (s)
DEFAULT_TOLERANCE_S = 0.25


def step_times(steps: pd.DataFrame) -> np.ndarray:
    """The step times of a step table: the column named by ``attrs['event']`` (default ``t_peak_s``)."""
    event = steps.attrs.get("event", "t_peak_s")
    if event not in steps.columns:
        raise InputError(f"the step table has no column {event!r} (attrs['event']); build it with gaitml.steps.make_step_table.")
    return steps[event].to_numpy(dtype=float)


def count_accuracy(n_detected: int, n_true: int) -> float:
    """``1 - |n_detected - n_true| / n_true`` (may be negative when far over-counting)."""
    if n_true <= 0:
        raise InputError(f"`n_true` must be positive to compute a count accuracy, got {n_true}.")
    return 1.0 - abs(int(n_detected) - int(n_true)) / float(n_true)


def match_steps(detected_s: np.ndarray, true_s: np.ndarray, tolerance_s: float = DEFAULT_TOLERANCE_S) -> np.ndarray:
    """One-to-one matching of detected to true step times within ``tolerance_s``.

    The matching is optimal: among all one-to-one pairings with
    ``|t_det - t_true| <= tolerance_s`` it has the most pairs and, among those,
    the smallest total absolute time difference. Both lists are sorted; the
    problem splits into independent blocks of times linked through the
    tolerance, and each block is solved with the Hungarian algorithm
    (:func:`scipy.optimize.linear_sum_assignment`) on a cost of
    ``|dt| - BIG`` for admissible pairs (so the pair count dominates).

    Returns
    -------
    ndarray (n_pairs, 2) of int: indices into the sorted ``detected_s`` and
    ``true_s`` (sorted order is the caller's order when they are sorted).
    """
    det = np.asarray(detected_s, dtype=float)
    tru = np.asarray(true_s, dtype=float)
    if tolerance_s <= 0 or not np.isfinite(tolerance_s):
        raise InputError(f"`tolerance_s` must be a positive number, got {tolerance_s!r}.")
    if det.ndim != 1 or tru.ndim != 1:
        raise InputError("step times must be 1-D arrays of seconds.")
    if len(det) == 0 or len(tru) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    od, ot = np.argsort(det, kind="stable"), np.argsort(tru, kind="stable")
    d, t = det[od], tru[ot]
    # blocks: merge both sorted lists; a new block starts where the gap to the previous time exceeds the tolerance
    allt = np.concatenate([d, t])
    src = np.concatenate([np.zeros(len(d), np.int8), np.ones(len(t), np.int8)])
    idx = np.concatenate([np.arange(len(d)), np.arange(len(t))])
    order = np.argsort(allt, kind="stable")
    allt, src, idx = allt[order], src[order], idx[order]
    breaks = np.flatnonzero(np.diff(allt) > tolerance_s) + 1
    pairs = []
    big = 1e6
    for blk_src, blk_idx in zip(np.split(src, breaks), np.split(idx, breaks), strict=True):
        di = blk_idx[blk_src == 0]
        ti = blk_idx[blk_src == 1]
        if len(di) == 0 or len(ti) == 0:
            continue
        if len(di) == 1 and len(ti) == 1:
            if abs(d[di[0]] - t[ti[0]]) <= tolerance_s:
                pairs.append((di[0], ti[0]))
            continue
        dt = np.abs(d[di][:, None] - t[ti][None, :])
        ok = dt <= tolerance_s
        cost = np.where(ok, dt - big, 0.0)
        r, c = linear_sum_assignment(cost)
        keep = ok[r, c]
        pairs.extend(zip(di[r[keep]], ti[c[keep]], strict=True))
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    p = np.asarray(pairs, dtype=np.int64)
    p = np.column_stack([od[p[:, 0]], ot[p[:, 1]]])
    return p[np.argsort(p[:, 1])]


def evaluate_steps(steps: pd.DataFrame, true_s: np.ndarray, *, tolerance_s: float = DEFAULT_TOLERANCE_S, n_true: int | None = None) -> dict:
    """Evaluate a step table against true step times.

    Parameters
    ----------
    steps : DataFrame
        A detector's step table (its ``attrs['event']`` column is the step time).
    true_s : array of float, or None
        True step times (s). May be None when only ``n_true`` is known (then only
        the count accuracy is computed).
    tolerance_s : float
        Matching tolerance (s).
    n_true : int, optional
        True step count (default ``len(true_s)``).

    Returns
    -------
    dict: ``n_detected``, ``n_true``, ``count_accuracy``; with true times also
    ``n_matched``, ``precision``, ``recall``, ``f1``, ``timing_offset_s`` (mean
    signed detected - true time over matched pairs; negative = early),
    ``timing_mae_s``, ``period_error_s`` (mean |detected period - true period|
    over matched pairs whose previous steps are matched too; the true period is
    the interval to the previous true step), ``period_bias_s`` (mean signed).
    """
    det = step_times(steps)
    if n_true is None:
        if true_s is None:
            raise InputError("give the true step times or n_true to evaluate steps.")
        n_true = len(true_s)
    out: dict = {
        "n_detected": len(det),
        "n_true": int(n_true),
        "count_accuracy": count_accuracy(len(det), n_true),
        "tolerance_s": float(tolerance_s),
    }
    if true_s is None:
        return out
    tru = np.sort(np.asarray(true_s, dtype=float))
    order = np.argsort(det, kind="stable")
    det = det[order]
    pairs = match_steps(det, tru, tolerance_s)
    m = len(pairs)
    precision = m / len(det) if len(det) else 0.0
    recall = m / len(tru) if len(tru) else 0.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall > 0 else 0.0
    out.update(n_matched=m, precision=precision, recall=recall, f1=f1)
    if m:
        dt = det[pairs[:, 0]] - tru[pairs[:, 1]]
        out.update(timing_offset_s=float(dt.mean()), timing_mae_s=float(np.abs(dt).mean()))
        # period error: consecutive matched pairs (detected k-1,k matched to true j-1,j)
        cons = (np.diff(pairs[:, 0]) == 1) & (np.diff(pairs[:, 1]) == 1)
        if cons.any():
            dp = np.diff(det[pairs[:, 0]])[cons] - np.diff(tru[pairs[:, 1]])[cons]
            out.update(period_error_s=float(np.abs(dp).mean()), period_bias_s=float(dp.mean()))
        else:
            out.update(period_error_s=None, period_bias_s=None)
    else:
        out.update(timing_offset_s=None, timing_mae_s=None, period_error_s=None, period_bias_s=None)
    return out
