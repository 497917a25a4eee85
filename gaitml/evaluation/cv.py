"""Grouped cross-validation of a model kind on a :class:`~gaitml.models.WindowDataset`.

Schemes (``cv.scheme`` in an experiment config):

- ``train-one-test-rest``: paper 003 sec. 3.3 protocol ("each experiment uses
  this sample as the training set and the others as the test set"): one fold per
  group, trained on that group only, tested on all the others.
- ``leave-one-group-out``: one fold per group, trained on all the others,
  tested on it (leave-one-subject-out with ``group = "subject"``).
- ``group-kfold``: ``n_splits`` folds of whole groups (scikit-learn GroupKFold).

Folds run in parallel through joblib (``n_jobs``) with a tqdm progress bar on
stderr. Each fold reports accuracy and macro-F1 before and after the
adjacent-window correction (paper 003 sec. 3.4), applied to the test windows of
each recording in time order.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time

import numpy as np
import pandas as pd

from gaitml.errors import ConfigError, InputError

__all__ = ["CV_SCHEMES", "CVResult", "cross_validate", "make_splits", "check_groups", "TrainOneTestRest"]

CV_SCHEMES = ("train-one-test-rest", "leave-one-group-out", "group-kfold")


class TrainOneTestRest:
    """Paper 003 protocol: fit on one group, test on every other group (one fold per group)."""

    def get_n_splits(self, X=None, y=None, groups=None) -> int:
        return len(np.unique(groups))

    def split(self, X, y=None, groups=None):
        g = np.asarray(groups)
        for u in np.unique(g):
            yield np.flatnonzero(g == u), np.flatnonzero(g != u)


def check_groups(scheme: str, groups, n_splits: int = 5, *, group_key: str = "group") -> int:
    """Raise ConfigError when the data has too few groups for ``scheme``; return the number of folds."""
    if scheme not in CV_SCHEMES:
        raise ConfigError(f"cv.scheme = {scheme!r} is not a scheme; allowed: {', '.join(CV_SCHEMES)}.")
    uniq = np.unique(np.asarray(groups).astype(str))
    n = len(uniq)
    if scheme == "group-kfold":
        if n_splits < 2:
            raise ConfigError(f"cv.n_splits = {n_splits} must be >= 2 for group-kfold.")
        if n < n_splits:
            raise ConfigError(
                f"cv.scheme = 'group-kfold' with n_splits = {n_splits} needs at least {n_splits} groups, "
                f"but data.group = {group_key!r} has {n} ({', '.join(uniq[:5])}); lower cv.n_splits or use more groups."
            )
        return n_splits
    if n < 2:
        raise ConfigError(
            f"cv.scheme = {scheme!r} needs at least 2 groups, but data.group = {group_key!r} has {n} "
            f"({', '.join(uniq[:5])}); use another group column or more recordings."
        )
    return n


def make_splits(scheme: str, groups, n_splits: int = 5) -> list[tuple[np.ndarray, np.ndarray]]:
    """(train_rows, test_rows) of every fold, deterministic."""
    from sklearn.model_selection import GroupKFold, LeaveOneGroupOut

    check_groups(scheme, groups, n_splits)
    g = np.asarray(groups).astype(str)
    dummy = np.zeros(len(g))
    if scheme == "train-one-test-rest":
        splitter = TrainOneTestRest()
    elif scheme == "leave-one-group-out":
        splitter = LeaveOneGroupOut()
    else:
        splitter = GroupKFold(n_splits=n_splits)
    return [(np.asarray(a), np.asarray(b)) for a, b in splitter.split(dummy, dummy, g)]


@dataclasses.dataclass
class CVResult:
    """Outcome of :func:`cross_validate`.

    Attributes
    ----------
    folds : DataFrame
        One row per fold: ``fold``, ``train_groups`` and ``test_groups`` (group
        names joined by ``;``), ``n_train``, ``n_test``,
        ``accuracy``, ``macro_f1``, ``accuracy_corrected``, ``macro_f1_corrected``,
        ``fit_s``.
    predictions : DataFrame
        One row per tested window and fold: ``fold``, ``recording``, ``group``,
        ``t_start_s``, ``t_end_s``, ``label``, ``pred``, ``pred_corrected``.
    before, after : dict
        :func:`~gaitml.evaluation.classification.classification_metrics` of all
        test predictions pooled, before and after the correction.
    labels : list of str
    """

    folds: pd.DataFrame
    predictions: pd.DataFrame
    before: dict
    after: dict
    labels: list

    def summary(self) -> dict:
        """Headline numbers (pooled, and the mean and std over folds)."""
        f = self.folds
        return {
            "accuracy_before": self.before["accuracy"],
            "accuracy_after": self.after["accuracy"],
            "macro_f1_before": self.before["macro_f1"],
            "macro_f1_after": self.after["macro_f1"],
            "fold_accuracy_mean_before": float(f["accuracy"].mean()),
            "fold_accuracy_std_before": float(f["accuracy"].std(ddof=0)),
            "fold_accuracy_mean_after": float(f["accuracy_corrected"].mean()),
            "fold_accuracy_std_after": float(f["accuracy_corrected"].std(ddof=0)),
            "n_folds": int(len(f)),
            "n_test_predictions": int(self.before["n"]),
        }


def _fit_predict(kind, params, seed, X_train, y_train, X_test):
    from gaitml.models import make_model

    t0 = time.perf_counter()
    model = make_model(kind, params, seed=seed)
    model.fit(X_train, y_train)
    fit_s = time.perf_counter() - t0
    return np.asarray(model.predict(X_test)).astype(str), fit_s


def cross_validate(
    dataset,
    kind: str,
    params: dict | None = None,
    *,
    scheme: str = "leave-one-group-out",
    n_splits: int = 5,
    n_jobs: int = 1,
    seed: int = 0,
    labels: list[str] | None = None,
    progress: bool = True,
    description: str = "cv",
    test_dataset=None,
) -> CVResult:
    """Cross-validate model ``kind`` on a window data set, grouped by ``dataset.groups``.

    Parameters
    ----------
    dataset : WindowDataset
    kind, params : model kind and constructor parameters (:func:`gaitml.models.make_model`)
    scheme : one of :data:`CV_SCHEMES`
    n_splits : folds of 'group-kfold'
    n_jobs : joblib workers for the folds (1 = in process; -1 = all cores)
    seed : model seed (the same in every fold)
    labels : order of labels in the metrics (default: sorted labels of the data)
    progress : show a tqdm bar on stderr
    test_dataset : WindowDataset or None
        The windows to score each fold on, when they differ from the training windows
        (training on augmented copies, :mod:`gaitml.pipeline.augment`, scored on the
        recordings as they were): each fold trains on ``dataset``'s windows of its training
        groups and is scored on ``test_dataset``'s windows of its test groups. Its groups
        must be among those of ``dataset``. Default: ``dataset`` itself.

    Returns
    -------
    CVResult
    """
    from joblib import Parallel, delayed
    from tqdm.auto import tqdm

    from gaitml.evaluation.classification import classification_metrics, correct_by_recording
    from gaitml.models import model_class

    input_kind = model_class(kind).input_kind
    X = dataset.inputs(input_kind)
    y = dataset.y
    groups = dataset.groups
    splits = make_splits(scheme, groups, n_splits)
    test = dataset if test_dataset is None else test_dataset
    X_test, y_test, groups_test = (X, y, groups) if test_dataset is None else (test.inputs(input_kind), test.y, test.groups)
    if test_dataset is not None:
        if not set(groups_test) <= set(groups):
            raise InputError(
                "cross_validate: test_dataset holds groups that dataset does not "
                f"({', '.join(sorted(set(groups_test) - set(groups))[:5])}); build both from the same recordings."
            )
        # the same folds, scored on the test windows of each fold's test groups
        splits_test = [np.flatnonzero(np.isin(groups_test, np.unique(groups[te]))) for _tr, te in splits]
    else:
        splits_test = [te for _tr, te in splits]
    labs = list(labels) if labels else sorted(set(y))
    for k, (tr, _te) in enumerate(splits):
        if len(np.unique(y[tr])) < 2:
            raise InputError(
                f"fold {k} of {scheme} has fewer than 2 classes in its training windows ({', '.join(sorted({str(c) for c in y[tr]}))}); use another scheme or more data per group."
            )
    tasks = (delayed(_fit_predict)(kind, params, seed, X[tr], y[tr], X_test[te]) for (tr, _te), te in zip(splits, splits_test, strict=True))
    bar = tqdm(total=len(splits), desc=description, file=sys.stderr, disable=not progress, leave=False)
    results = []
    # never more workers than folds or cores (n_jobs = 5000 must not start 5000 processes)
    cores = os.cpu_count() or 1
    n_jobs = max(1, min(cores if n_jobs < 0 else n_jobs, len(splits), cores))
    if n_jobs == 1:
        for t in tasks:
            fn, a, kw = t
            results.append(fn(*a, **kw))
            bar.update(1)
    else:
        for r in Parallel(n_jobs=n_jobs, return_as="generator")(tasks):
            results.append(r)
            bar.update(1)
    bar.close()
    rows, preds = [], []
    win = test.windows
    y, test_groups = y_test, groups_test
    for k, ((tr, _te), te, (pred, fit_s)) in enumerate(zip(splits, splits_test, results, strict=True)):
        rec = win["recording"].to_numpy()[te]
        corr = correct_by_recording(pred, rec, win["t_start_s"].to_numpy()[te])
        mb = classification_metrics(y[te], pred, labs)
        ma = classification_metrics(y[te], corr, labs)
        rows.append(
            {
                "fold": k,
                "train_groups": ";".join(sorted(set(groups[tr]))),
                "test_groups": ";".join(sorted(set(test_groups[te]))),
                "n_train": int(len(tr)),
                "n_test": int(len(te)),
                "accuracy": mb["accuracy"],
                "macro_f1": mb["macro_f1"],
                "accuracy_corrected": ma["accuracy"],
                "macro_f1_corrected": ma["macro_f1"],
                "fit_s": float(fit_s),
            }
        )
        preds.append(
            pd.DataFrame(
                {
                    "fold": k,
                    "recording": rec,
                    "group": test_groups[te],
                    "t_start_s": win["t_start_s"].to_numpy()[te],
                    "t_end_s": win["t_end_s"].to_numpy()[te],
                    "label": y[te],
                    "pred": pred,
                    "pred_corrected": corr,
                }
            )
        )
    predictions = pd.concat(preds, ignore_index=True)
    before = classification_metrics(predictions["label"], predictions["pred"], labs)
    after = classification_metrics(predictions["label"], predictions["pred_corrected"], labs)
    return CVResult(folds=pd.DataFrame(rows), predictions=predictions, before=before, after=after, labels=labs)
