"""Fitting the domain record: :class:`DomainCheck` (a scikit-learn style estimator) and :func:`fit_domain`.

The thresholds are quantiles of **held-out** distances: the training groups (subjects)
are split into up to :data:`HELDOUT_FOLDS` folds, the standardisation, Gaussians and
gravity set fitted on the other folds and the distances measured on the held-out one
(an in-sample threshold would be optimistic; it is kept beside it for comparison).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import BaseAlgorithm, Interval
from gaitml.errors import ModelError
from gaitml.models.domain._descriptors import DYNAMICS_NAMES
from gaitml.models.domain._distance import _class_gaussians, _min_mahalanobis, _standardiser
from gaitml.models.domain._gravity import _nearest_angle, _subsample_dirs
from gaitml.models.domain._record import ChunkContext, DomainModel
from gaitml.models.domain._running import DYNAMICS_SPAN, dynamics_grid_step, span_medians

__all__ = ["DEFAULT_QUANTILE", "HELDOUT_FOLDS", "DomainCheck", "fit_domain"]

#: Default quantile of the held-out distances used as thresholds.
DEFAULT_QUANTILE = 0.99
#: Folds over the training groups for the held-out thresholds.
HELDOUT_FOLDS = 5


class DomainCheck(BaseAlgorithm):
    """Learn a model's training domain and flag new windows outside it (see :mod:`gaitml.models.domain`).

    Parameters
    ----------
    feature_names : list of str
        The columns of ``X``.
    feature_set : str
        Name of the feature set ``X`` holds (recorded for the model card).
    frame : {"phone", "gravity"}
        The frame of the features; the gravity direction is checked in the phone frame only.
    quantile : float
        Quantile of the held-out distances used as thresholds, in [0.5, 1).
    random_state : int
        Seeds the subset of kept training gravity directions.
    dynamics_span : int
        Windows in the running span of the dynamics decision (:data:`DYNAMICS_SPAN`).
    dynamics_every : int or None
        Grid step of the computed windows; None: :func:`dynamics_grid_step` of the span.

    Attributes
    ----------
    record_ : DomainModel
        The fitted record (what a saved model stores).
    classes_ : list of str
    """

    _action_method = "fit"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "random_state": [Interval(integer=True)],
    }

    def __init__(
        self,
        *,
        feature_names=(),
        feature_set: str = "",
        frame: str = "phone",
        quantile: float = DEFAULT_QUANTILE,
        random_state: int = 0,
        dynamics_span: int = DYNAMICS_SPAN,
        dynamics_every: int | None = None,
    ):
        self.feature_names = feature_names
        self.feature_set = feature_set
        self.frame = frame
        self.quantile = quantile
        self.random_state = random_state
        self.dynamics_span = dynamics_span
        self.dynamics_every = dynamics_every

    def fit(self, X, y, groups, *, gravity=None, positions=None, dynamics=None, sequence=None) -> DomainCheck:
        """Fit the record on training windows.

        Parameters
        ----------
        X : (n, p) training features (raw units), ``feature_names`` order.
        y : (n,) window labels.
        groups : (n,) cross-validation group (subject) of every window.
        gravity : (n, 3) window gravity unit vectors in the phone frame (:func:`window_gravity`);
            None: unknown (NaN), the gravity test then accepts every window.
        positions : (n,) carrying position of every window, optional.
        dynamics : (n, 13) :func:`orientation_dynamics` of the windows, optional (the dynamics part).
        sequence : (n,) recording of every window, needed with ``dynamics`` (rows in time order).
        """
        self._validate_params()
        X = np.asarray(X, dtype=float)
        grav = np.full((len(X), 3), np.nan) if gravity is None else gravity
        self.record_ = _fit_record(
            X,
            y,
            groups,
            grav,
            feature_names=list(self.feature_names)
            if len(self.feature_names)
            else [f"x{i}" for i in range(X.shape[1] if X.ndim == 2 else 0)],
            feature_set=self.feature_set,
            frame=self.frame,
            positions=positions,
            quantile=self.quantile,
            seed=self.random_state,
            dynamics=dynamics,
            sequence=sequence,
            dynamics_every=self.dynamics_every,
            dynamics_span=self.dynamics_span,
        )
        self.classes_ = list(self.record_.classes)
        return self

    @classmethod
    def from_record(cls, record: DomainModel) -> DomainCheck:
        """A fitted estimator around a stored record (e.g. ``load_model(...).domain``)."""
        dyn = record.dynamics or {}
        est = cls(
            feature_names=list(record.feature_names),
            feature_set=record.feature_set,
            frame=record.frame,
            quantile=record.quantile,
            dynamics_span=int(dyn.get("span", DYNAMICS_SPAN)),
            dynamics_every=dyn.get("every"),
        )
        est.record_ = record
        est.classes_ = list(record.classes)
        return est

    def _fitted(self) -> DomainModel:
        rec = getattr(self, "record_", None)
        if rec is None:
            raise ModelError("this DomainCheck is not fitted; call fit(X, y, groups) first.")
        return rec

    def check_windows(self, X, gravity=None, dynamics=None) -> pd.DataFrame:
        """Per-window distances and flags (:meth:`DomainModel.check`) as a table.

        Columns ``distance``, ``gravity_angle_rad``, ``dynamics_distance`` (NaN where a
        test is not made) and ``in_domain`` (bool), one row per row of ``X``.
        """
        return pd.DataFrame(self._fitted().check(X, gravity, dynamics))

    def chunk_context(self, sampling_rate_hz: float) -> ChunkContext:
        """The context a chunked prediction needs around each chunk (:meth:`DomainModel.chunk_context`)."""
        return self._fitted().chunk_context(sampling_rate_hz)


def fit_domain(
    X,
    y,
    groups,
    gravity,
    *,
    feature_names,
    feature_set: str,
    frame: str,
    positions=None,
    quantile: float = DEFAULT_QUANTILE,
    seed: int = 0,
    dynamics=None,
    sequence=None,
    dynamics_every: int | None = None,
    dynamics_span: int | None = None,
) -> DomainModel:
    """The fitted :class:`DomainModel` of a training set: ``DomainCheck(...).fit(...).record_``.

    Parameters as :class:`DomainCheck` and :meth:`DomainCheck.fit` (``seed`` is its
    ``random_state``; ``dynamics_span`` None is :data:`DYNAMICS_SPAN`).
    """
    return (
        DomainCheck(
            feature_names=list(feature_names),
            feature_set=feature_set,
            frame=frame,
            quantile=quantile,
            random_state=seed,
            dynamics_span=DYNAMICS_SPAN if dynamics_span is None else dynamics_span,
            dynamics_every=dynamics_every,
        )
        .fit(X, y, groups, gravity=gravity, positions=positions, dynamics=dynamics, sequence=sequence)
        .record_
    )


def _fit_record(
    X,
    y,
    groups,
    gravity,
    *,
    feature_names,
    feature_set: str,
    frame: str,
    positions=None,
    quantile: float = DEFAULT_QUANTILE,
    seed: int = 0,
    dynamics=None,
    sequence=None,
    dynamics_every: int | None = None,
    dynamics_span: int | None = None,
) -> DomainModel:
    """Fit the domain record of a training set (:func:`fit_domain`; see :mod:`gaitml.models.domain`).

    Parameters
    ----------
    X : (n, p) training features (raw units), ``feature_names`` order.
    y : (n,) window labels.
    groups : (n,) cross-validation group (subject) of every window; the held-out
        thresholds come from folds over these groups.
    gravity : (n, 3) window gravity unit vectors in the phone frame (:func:`window_gravity`).
    feature_names, feature_set, frame : what ``X`` is.
    positions : (n,) carrying position of every window, optional (``"unknown"``).
    quantile : threshold quantile of the held-out distances (0.5-1).
    seed : seeds the gravity-direction subset.
    dynamics : (n, 13) :func:`orientation_dynamics` of the windows, optional: when
        given, the orientation-dynamics part is recorded (one Gaussian per
        ``mode|position`` fitted on every window; threshold = the quantile of the
        held-out span medians over :data:`DYNAMICS_SPAN` windows, computed on the grid
        of every ``dynamics_every``-th window as the check does, :func:`span_medians`,
        pooled over the grid's phases: every window's statistic once per phase).
    sequence : (n,) recording of every window (the span never crosses recordings);
        needed with ``dynamics``. Rows of one recording must be in time order.
    dynamics_every : the grid step recorded with the dynamics part (default
        :func:`dynamics_grid_step` of :data:`DYNAMICS_SPAN`, i.e. :data:`DYNAMICS_EVERY`; 1 gives
        the statistic over every window of records written before the grid).
    dynamics_span : windows in the running span recorded with the dynamics part (default
        :data:`DYNAMICS_SPAN`); the grid step then defaults to :func:`dynamics_grid_step` of it.
    """
    from sklearn.model_selection import GroupKFold

    X = np.asarray(X, dtype=float)
    y = np.asarray(y).astype(str)
    groups = np.asarray(groups).astype(str)
    gravity = np.asarray(gravity, dtype=float).reshape(-1, 3)
    n = len(X)
    if not (len(y) == len(groups) == len(gravity) == n) or n < 2:
        raise ModelError(
            f"the domain fit needs matching rows (X {n}, y {len(y)}, groups {len(groups)}, gravity {len(gravity)}), at least 2."
        )
    if not 0.5 <= float(quantile) < 1.0:
        raise ModelError(f"domain quantile must be in [0.5, 1), got {quantile}.")
    span = DYNAMICS_SPAN if dynamics_span is None else int(dynamics_span)
    if span < 1:
        raise ModelError(f"the dynamics span must be at least 1 window, got {dynamics_span}.")
    if dynamics is not None:
        dynamics = np.asarray(dynamics, dtype=float)
        if dynamics.shape != (n, len(DYNAMICS_NAMES)) or sequence is None or len(sequence) != n:
            raise ModelError(f"the domain fit needs dynamics of shape ({n}, {len(DYNAMICS_NAMES)}) and one sequence id per window.")
    rng = np.random.default_rng(seed)
    classes = sorted({str(c) for c in y})
    gravity_check = frame == "phone"
    ug = np.unique(groups)
    k = min(HELDOUT_FOLDS, len(ug))
    held_d = np.full(n, np.nan)
    held_a = np.full(n, np.nan)
    held_q = np.full(n, np.nan)
    pos = np.full(n, "unknown", dtype=object) if positions is None else np.asarray(positions).astype(str)
    dyn_labels = np.char.add(np.char.add(y.astype(str), "|"), pos.astype(str)) if dynamics is not None else None
    dyn_ok = np.isfinite(dynamics).all(axis=1) if dynamics is not None else None
    if k >= 2:
        for tr, te in GroupKFold(n_splits=k).split(X, y, groups):
            if dynamics is not None:
                held_q[te] = _dynamics_fit_distance(dynamics, dyn_labels, dyn_ok, tr, te)
            c, s = _standardiser(X[tr])
            means, precs = _class_gaussians((X[tr] - c) / s, y[tr], sorted(set(y[tr])))
            held_d[te] = _min_mahalanobis((X[te] - c) / s, means, precs)
            held_a[te] = _nearest_angle(gravity[te], _subsample_dirs(gravity[tr], rng))
        scheme = f"{k}-fold over the {len(ug)} training groups (subjects)"
    else:
        scheme = "in-sample (a single training group: no held-out threshold possible)"
    center, scale = _standardiser(X)
    Z = (X - center) / scale
    means, precs = _class_gaussians(Z, y, classes)
    in_d = _min_mahalanobis(Z, means, precs)
    dirs = _subsample_dirs(gravity, rng)
    # in-sample angle: to the nearest *other* stored direction would be 0 for stored ones; use all training windows
    in_a = _nearest_angle(gravity, dirs)
    if k < 2:
        held_d, held_a = in_d, in_a
    q = float(quantile)
    fin = np.isfinite(gravity).all(axis=1)
    gmean = gravity[fin].mean(axis=0) if fin.any() else np.array([0.0, 0.0, 1.0])
    gmean = gmean / max(float(np.linalg.norm(gmean)), 1e-12)
    to_mean = np.degrees(np.arccos(np.clip(gravity[fin] @ gmean, -1, 1))) if fin.any() else np.zeros(1)
    pos_counts = {str(p): int((pos == p).sum()) for p in sorted(set(pos))}
    summary = {
        "n_windows": int(n),
        "n_groups": int(len(ug)),
        "heldout": scheme,
        "gravity_mean": [round(float(v), 4) for v in gmean],
        "gravity_angle_to_mean_deg": {f"q{int(p)}": round(float(np.percentile(to_mean, p)), 2) for p in (50, 90, 99)},
        "gravity_directions_kept": int(len(dirs)),
        "distance_threshold_heldout_vs_in_sample": [float(np.nanquantile(held_d, q)), float(np.quantile(in_d, q))],
    }
    dyn_record = None
    dyn_arrays: dict = {}
    if dynamics is not None:
        every = np.arange(n)
        in_q = _dynamics_fit_distance(dynamics, dyn_labels, dyn_ok, every, every)
        seq = np.asarray(sequence).astype(str)
        every = dynamics_grid_step(span) if dynamics_every is None else int(dynamics_every)

        def pooled(d):  # the check's statistic on the grid, each of its phases in turn (every window once per phase)
            return np.concatenate([span_medians(d, span, every, seq, phase) for phase in range(every)])

        span_held = pooled(held_q if k >= 2 else in_q)
        span_in = pooled(in_q)
        labels = sorted(set(dyn_labels[dyn_ok]))
        c_q, s_q = _standardiser(dynamics[dyn_ok])
        m_q, p_q = _class_gaussians((dynamics[dyn_ok] - c_q) / s_q, dyn_labels[dyn_ok], labels)
        dyn_record = {
            "labels": labels,
            "span": span,
            "every": every,
            "threshold": float(np.nanquantile(span_held, q)),
            "threshold_in_sample": float(np.nanquantile(span_in, q)),
        }
        dyn_arrays = {"dyn_center": c_q, "dyn_scale": s_q, "dyn_means": m_q, "dyn_precisions": p_q}
        summary["dynamics_threshold_heldout_vs_in_sample"] = [dyn_record["threshold"], dyn_record["threshold_in_sample"]]
    return DomainModel(
        feature_set=feature_set,
        frame=frame,
        feature_names=list(feature_names),
        classes=classes,
        positions=pos_counts,
        quantile=q,
        distance_threshold=float(np.nanquantile(held_d, q)),
        distance_threshold_in_sample=float(np.quantile(in_d, q)),
        gravity_check=gravity_check,
        gravity_threshold_rad=float(np.nanquantile(held_a, q)) if np.isfinite(held_a).any() else float(np.pi),
        gravity_threshold_in_sample_rad=float(np.nanquantile(in_a, q)) if np.isfinite(in_a).any() else float(np.pi),
        arrays={
            "center": center,
            "scale": scale,
            "class_means": means,
            "class_precisions": precs,
            "gravity_dirs": dirs if len(dirs) else np.zeros((0, 3)),
            **dyn_arrays,
        },
        summary=summary,
        dynamics=dyn_record,
    )


def _dynamics_fit_distance(Q, labels, ok, tr, te) -> np.ndarray:
    """Dynamics distances of rows ``te`` to Gaussians fitted on rows ``tr`` (finite rows only; inf for non-finite ``te`` rows)."""
    tr = tr[ok[tr]]
    c, s = _standardiser(Q[tr])
    means, precs = _class_gaussians((Q[tr] - c) / s, labels[tr], sorted(set(labels[tr])))
    out = np.full(len(te), np.inf)
    good = ok[te]
    out[good] = _min_mahalanobis((Q[te][good] - c) / s, means, precs)
    return out
