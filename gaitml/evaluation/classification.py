"""Classification metrics for motion-mode recognition (paper 003 sec. 3.3-3.4).

Accuracy (the paper's "recognition rate"), macro-F1, per-class precision /
recall / F1 / support and the confusion matrix, plus the adjacent-window
correction applied per recording in time order.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = ["classification_metrics", "confusion_table", "correct_by_recording"]


def classification_metrics(y_true: Sequence, y_pred: Sequence, labels: Sequence[str] | None = None) -> dict:
    """Accuracy, macro-F1, per-class scores and the confusion matrix.

    Parameters
    ----------
    y_true, y_pred : sequences of str, same length
    labels : list of str, optional
        Row/column order of the confusion matrix and the classes averaged by
        macro-F1 (default: sorted union of both). Classes absent from ``y_true``
        get recall 0 and support 0; precision of a never-predicted class is 0.

    Returns
    -------
    dict
        ``accuracy``, ``macro_f1``, ``n``, ``labels``, ``per_class`` ({label:
        {precision, recall, f1, support}}), ``confusion`` (list of lists, rows
        true, columns predicted).
    """
    t = np.asarray(y_true).astype(str)
    p = np.asarray(y_pred).astype(str)
    if t.shape != p.shape or t.ndim != 1:
        raise InputError(f"y_true and y_pred must be 1-D of the same length, got {t.shape} and {p.shape}.")
    labs = [str(x) for x in labels] if labels is not None else sorted(set(t) | set(p))
    index = {lab: i for i, lab in enumerate(labs)}
    k = len(labs)
    cm = np.zeros((k, k), dtype=np.int64)
    ti = np.array([index.get(x, -1) for x in t], dtype=np.int64)
    pi = np.array([index.get(x, -1) for x in p], dtype=np.int64)
    ok = (ti >= 0) & (pi >= 0)
    np.add.at(cm, (ti[ok], pi[ok]), 1)
    tp = np.diag(cm).astype(float)
    support = cm.sum(axis=1).astype(float)
    predicted = cm.sum(axis=0).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        precision = np.where(predicted > 0, tp / predicted, 0.0)
        recall = np.where(support > 0, tp / support, 0.0)
        f1 = np.where(precision + recall > 0, 2 * precision * recall / (precision + recall), 0.0)
    present = support > 0
    n = len(t)
    return {
        "accuracy": float((t == p).mean()) if n else float("nan"),
        "macro_f1": float(f1[present].mean()) if present.any() else float("nan"),
        "n": int(n),
        "labels": labs,
        "per_class": {
            lab: {"precision": float(precision[i]), "recall": float(recall[i]), "f1": float(f1[i]), "support": int(support[i])}
            for i, lab in enumerate(labs)
        },
        "confusion": cm.tolist(),
    }


def confusion_table(metrics: dict) -> pd.DataFrame:
    """The confusion matrix of :func:`classification_metrics` as a labelled DataFrame."""
    labs = metrics["labels"]
    return pd.DataFrame(metrics["confusion"], index=pd.Index(labs, name="true"), columns=labs)


def correct_by_recording(y_pred: Sequence, recording: Sequence, order: Sequence[float]) -> np.ndarray:
    """Apply the adjacent-window correction (paper 003 sec. 3.4) per recording, in time order.

    Parameters
    ----------
    y_pred : sequence of str, shape (n,)
        Predicted label of every window.
    recording : sequence, shape (n,)
        Source recording of every window; windows of different recordings are
        never corrected against each other.
    order : sequence of float, shape (n,)
        Time of every window (e.g. ``t_start_s``) giving the sequence order.

    Returns
    -------
    ndarray of str, shape (n,)
        Corrected labels in the input order.

    Notes
    -----
    Windows dropped before classification (weak label majority) are absent, so
    the rule sees the kept windows as consecutive; this is what a deployed
    classifier does not do (it sees every window), and is stated in the run
    report.
    """
    from gaitml.postprocess import adjacent_window_correction

    y = np.asarray(y_pred).astype(str)
    rec = np.asarray(recording)
    t = np.asarray(order, dtype=float)
    out = y.copy()
    for r in pd.unique(rec):
        idx = np.flatnonzero(rec == r)
        idx = idx[np.argsort(t[idx], kind="stable")]
        out[idx] = np.asarray(adjacent_window_correction(y[idx])).astype(str)
    return out
