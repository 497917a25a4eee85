"""The feature distance: standardisation, one Ledoit-Wolf Gaussian per class, the smallest Mahalanobis distance.

:func:`_min_mahalanobis` is the plain reference (one class at a time); the check's fast
paths (:class:`~gaitml.models.domain.DomainModel`) compute the same quadratic forms from
the stacked Cholesky factors of the precisions, and :func:`_feature_bound` /
:func:`_gravity_bound` give the input magnitudes under which its one-window path cannot
overflow.
"""

from __future__ import annotations

import numpy as np


def _standardiser(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    center = X.mean(axis=0)
    scale = X.std(axis=0)
    scale = np.where(scale > 1e-9 * (1.0 + np.abs(center)), scale, 1.0)  # constant features: unit scale
    return center, scale


def _class_gaussians(Z: np.ndarray, y: np.ndarray, classes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    from sklearn.covariance import LedoitWolf

    p = Z.shape[1]
    means = np.zeros((len(classes), p))
    precs = np.zeros((len(classes), p, p))
    for i, c in enumerate(classes):
        zc = Z[y == c]
        if len(zc) < 2:  # a class with one window: unit covariance around it
            means[i] = zc.mean(axis=0) if len(zc) else 0.0
            precs[i] = np.eye(p)
            continue
        lw = LedoitWolf(assume_centered=False).fit(zc)
        means[i] = lw.location_
        precs[i] = lw.precision_ if _positive_definite(lw.precision_) else _ridge_precision(lw.covariance_)
    return means, precs


#: Ridge (standardised feature units) added to a class covariance whose shrunk estimate is
#: singular: as lenient as the unit covariance of a one-window class, plus the spread seen.
RIDGE_UNITS = 1.0


def _positive_definite(a: np.ndarray) -> bool:
    if not np.all(np.isfinite(a)):
        return False
    try:
        np.linalg.cholesky(a)
    except np.linalg.LinAlgError:
        return False
    return True


def _ridge_precision(cov: np.ndarray) -> np.ndarray:
    """Precision of ``cov + RIDGE_UNITS * I`` (unit precision when even that fails).

    Ledoit-Wolf shrinkage can leave the covariance of a class with very few windows (two, say,
    in a small step-window data set) singular: its shrinkage intensity is estimated as 0. Such
    a class is treated like a one-window class (unit covariance in the standardised features)
    widened by the little spread its windows show, so its distances stay comparable with the
    other classes' instead of exploding off the line through its windows.
    """
    p = len(cov)
    prec = np.linalg.inv(cov + RIDGE_UNITS * np.eye(p))
    prec = 0.5 * (prec + prec.T)
    return prec if _positive_definite(prec) else np.eye(p)


def _min_mahalanobis(Z: np.ndarray, means: np.ndarray, precs: np.ndarray) -> np.ndarray:
    best = np.full(len(Z), np.inf)
    for m, P in zip(means, precs, strict=True):
        d = Z - m
        q = np.einsum("ij,ij->i", d @ P, d)
        best = np.minimum(best, np.sqrt(np.maximum(q, 0.0)))
    return best


#: The one-window path keeps every intermediate under this magnitude (far from overflow; see :func:`_feature_bound`).
_SAFE_MAGNITUDE = 1e300


def _feature_bound(center: np.ndarray, scale: np.ndarray, stacked: np.ndarray, offset: np.ndarray) -> float:
    """Largest ``|x|`` feature entry for which the distance arithmetic cannot overflow; -1 when none is safe.

    With every ``|x_i| <= B``: ``|z_i| <= (B + max|center|) / min(scale)`` and every
    entry of ``z L - m L`` is at most ``max|z| max_j sum_i |L_ij| + max|m L|``; the
    bound keeps that entry's square, summed over the ``p`` columns of a class, under
    :data:`_SAFE_MAGNITUDE`. No floating-point overflow or invalid operation can then
    occur, so the one-window path needs no ``np.errstate``.
    """
    parts = (center, scale, stacked, offset)
    if not all(np.isfinite(a).all() for a in parts) or not (scale > 0).all() or not len(center):
        return -1.0
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        a = float(np.abs(center).max())
        cmax = float(np.abs(stacked).sum(axis=0).max())
        z_max = (np.sqrt(_SAFE_MAGNITUDE / len(center)) - float(np.abs(offset).max())) / max(cmax, 1e-300)
        bound = min(1e100, min(z_max, _SAFE_MAGNITUDE) * float(scale.min()) - a)
    return float(bound) if np.isfinite(bound) and bound > 0 else -1.0


def _gravity_bound(dirs: np.ndarray) -> float:
    """Largest ``|g|`` entry for which ``g @ dirs.T`` cannot overflow; -1 without kept (finite) directions."""
    if not len(dirs) or not np.isfinite(dirs).all():
        return -1.0
    return min(1e100, _SAFE_MAGNITUDE / (3.0 * max(float(np.abs(dirs).max()), 1.0)))
