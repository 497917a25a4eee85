"""Metrics for zero-velocity detection against per-sample labels, points and intervals.

- :func:`per_sample_scores`: accuracy, precision, recall, F1 of a per-sample mask.
- :func:`point_recall`: fraction of reference points (e.g. motion-capture
  ``min_vel`` samples) that lie inside a detected interval.
- :func:`interval_recall`: fraction of reference intervals that contain a detection.
- :func:`over_segmentation`: detected intervals per reference interval and the
  fraction of reference intervals split into more than one detection.
- :func:`count_accuracy`: paper 001 Table 1's accuracy of the interval count.
- :func:`evaluate_stride_events`: all of the above against gaitmap stride events.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = [
    "count_accuracy",
    "evaluate_stride_events",
    "interval_recall",
    "over_segmentation",
    "per_sample_scores",
    "point_recall",
    "reference_stances",
]


def _as_intervals(detected) -> tuple[np.ndarray, np.ndarray]:
    """(start, end) arrays from an interval table, a detector (``zupts_``) or a bool mask."""
    if hasattr(detected, "zupts_"):
        detected = detected.zupts_
    if isinstance(detected, pd.DataFrame):
        return np.asarray(detected["start"], dtype=np.int64), np.asarray(detected["end"], dtype=np.int64)
    m = np.asarray(detected)
    if m.dtype == bool and m.ndim == 1:
        from gaitml.zupt._intervals import mask_runs

        return mask_runs(m)
    raise InputError("detections must be an interval table (start, end), a detector with zupts_, or a 1-D bool mask.")


def per_sample_scores(predicted: np.ndarray, reference: np.ndarray, *, valid: np.ndarray | None = None) -> dict:
    """Per-sample accuracy, precision, recall and F1 of zero-velocity (positive class).

    Parameters
    ----------
    predicted, reference : bool arrays, shape (n,)
    valid : bool array, optional
        Score only these samples (e.g. the annotated span).
    """
    p = np.asarray(predicted, dtype=bool)
    r = np.asarray(reference, dtype=bool)
    if p.shape != r.shape or p.ndim != 1:
        raise InputError(f"predicted and reference must be 1-D of the same length, got {p.shape} and {r.shape}.")
    if valid is not None:
        v = np.asarray(valid, dtype=bool)
        p, r = p[v], r[v]
    n = int(p.size)
    if n == 0:
        raise InputError("no samples to score; check the masks.")
    tp = int(np.sum(p & r))
    fp = int(np.sum(p & ~r))
    fn = int(np.sum(~p & r))
    tn = n - tp - fp - fn
    precision = tp / (tp + fp) if tp + fp else 0.0
    recall = tp / (tp + fn) if tp + fn else 0.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return {"n": n, "accuracy": (tp + tn) / n, "precision": precision, "recall": recall, "f1": f1, "tp": tp, "fp": fp, "fn": fn, "tn": tn}


def point_recall(detected, points: np.ndarray) -> tuple[float, np.ndarray]:
    """Fraction of reference sample indices that lie inside a detected ``[start, end)``.

    Returns
    -------
    recall : float
    hit : bool ndarray, one per point
    """
    s, e = _as_intervals(detected)
    pts = np.asarray(points, dtype=np.int64)
    if pts.size == 0:
        raise InputError("no reference points to score.")
    k = np.searchsorted(s, pts, side="right") - 1  # last interval starting at or before the point
    hit = (k >= 0) & (pts < e[np.clip(k, 0, None)]) if len(s) else np.zeros(pts.shape, dtype=bool)
    return float(hit.mean()), hit


def _overlap_counts(s: np.ndarray, e: np.ndarray, ref_start: np.ndarray, ref_end: np.ndarray) -> np.ndarray:
    """Number of detected intervals overlapping each reference interval (both sorted, half-open)."""
    rs = np.asarray(ref_start, dtype=np.int64)
    re = np.asarray(ref_end, dtype=np.int64)
    # detected intervals are disjoint and sorted: those overlapping [rs, re) are the ones
    # with start < re, minus those with end <= rs
    return np.searchsorted(s, re, side="left") - np.searchsorted(e, rs, side="right")


def interval_recall(detected, ref_start: np.ndarray, ref_end: np.ndarray) -> float:
    """Fraction of reference intervals ``[ref_start, ref_end)`` that overlap a detection."""
    s, e = _as_intervals(detected)
    c = _overlap_counts(s, e, ref_start, ref_end)
    if c.size == 0:
        raise InputError("no reference intervals to score.")
    return float(np.mean(c > 0))


def over_segmentation(detected, ref_start: np.ndarray, ref_end: np.ndarray) -> dict:
    """Detected intervals per reference interval and the share split into more than one.

    Returns
    -------
    dict
        ``mean_per_reference`` (mean count of overlapping detections),
        ``split_fraction`` (share of reference intervals overlapped by > 1
        detection), ``n_split``, ``counts`` (per reference interval).
    """
    s, e = _as_intervals(detected)
    c = _overlap_counts(s, e, ref_start, ref_end)
    if c.size == 0:
        raise InputError("no reference intervals to score.")
    return {"mean_per_reference": float(c.mean()), "split_fraction": float(np.mean(c > 1)), "n_split": int(np.sum(c > 1)), "counts": c}


def count_accuracy(n_detected: int, n_true: int) -> float:
    """Paper 001 Table 1: ``1 - |n_detected - n_true| / n_true`` (e.g. 88 for 87 -> 98.9 %)."""
    if n_true <= 0:
        raise InputError(f"`n_true` must be > 0, got {n_true}.")
    return 1.0 - abs(int(n_detected) - int(n_true)) / int(n_true)


def reference_stances(stride_events: pd.DataFrame) -> pd.DataFrame:
    """The reference stance of each gaitmap stride: ``[pre_ic, tc)`` around its ``min_vel``.

    gaitmap's strides run from one ``min_vel`` (mid-stance) to the next; the stance
    the stride starts in begins at the previous initial contact ``pre_ic`` and
    ends at toe-off ``tc``.
    """
    need = {"min_vel", "pre_ic", "tc"}
    if not need <= set(stride_events.columns):
        raise InputError(f"stride events need columns {sorted(need)}, got {list(stride_events.columns)}.")
    ev = stride_events.dropna(subset=list(need))
    return pd.DataFrame(
        {
            "start": ev["pre_ic"].to_numpy(dtype=np.int64),
            "end": ev["tc"].to_numpy(dtype=np.int64),
            "min_vel": ev["min_vel"].to_numpy(dtype=np.int64),
        }
    )


def evaluate_stride_events(detected, stride_events: pd.DataFrame) -> dict:
    """Score detections against gaitmap stride events (one row per stride).

    - ``min_vel_recall``: share of strides whose ``min_vel`` sample is inside a detection;
    - ``split_fraction``: share of strides whose stance ``[pre_ic, tc)`` overlaps more
      than one detected interval; ``intervals_per_stance``: mean count;
    - ``stance_recall``: share of stances that overlap a detection;
    - ``stride_extra_fraction``: share of strides (``min_vel`` to next ``min_vel``) in which
      more than one detected interval begins (exactly one, the landing, is expected: more
      means a split stance or a false detection in the swing);
    - ``count_accuracy``: paper 001's count accuracy of the detected intervals that
      overlap the annotated span (first stride start to last stride end) against the
      reference stances in it (the distinct ``min_vel`` samples incl. the last stride's end);
    - ``spurious_per_stance`` (``n_spurious``): detected intervals in the span that hold
      none of those ``min_vel`` samples, per reference stance (a stance split in two
      leaves one such piece; a false detection in a swing is one too). Unlike the count
      accuracy, misses and extras do not cancel.
    """
    s, e = _as_intervals(detected)
    st = reference_stances(stride_events)
    table = pd.DataFrame({"start": s, "end": e})
    rec, _ = point_recall(table, st["min_vel"].to_numpy())
    seg = over_segmentation(table, st["start"], st["end"])
    ss = stride_events["start"].to_numpy(dtype=np.int64)
    se = stride_events["end"].to_numpy(dtype=np.int64)
    starts_in = np.searchsorted(s, se, side="right") - np.searchsorted(s, ss, side="right")
    lo = int(np.min(stride_events["start"]))
    hi = int(np.max(stride_events["end"])) + 1
    n_in_span = int(np.sum((s < hi) & (e > lo)))
    ref_mv = np.unique(np.concatenate([stride_events["start"].to_numpy(), stride_events["end"].to_numpy()])).astype(np.int64)
    n_ref = int(ref_mv.size)
    k = np.searchsorted(s, ref_mv, side="right") - 1
    inside = (k >= 0) & (ref_mv < e[np.clip(k, 0, None)]) if len(s) else np.zeros(ref_mv.shape, dtype=bool)
    n_with_mv = int(np.unique(k[inside]).size)
    n_spurious = max(0, n_in_span - n_with_mv)
    return {
        "n_strides": int(len(st)),
        "n_intervals": int(len(s)),
        "min_vel_recall": rec,
        "stance_recall": interval_recall(table, st["start"], st["end"]),
        "split_fraction": seg["split_fraction"],
        "n_split": seg["n_split"],
        "intervals_per_stance": seg["mean_per_reference"],
        "stride_extra_fraction": float(np.mean(starts_in > 1)),
        "n_intervals_in_span": n_in_span,
        "n_stances_in_span": n_ref,
        "count_accuracy": count_accuracy(n_in_span, n_ref),
        "n_spurious": n_spurious,
        "spurious_per_stance": n_spurious / n_ref,
    }
