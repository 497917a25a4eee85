"""Plain per-window reference of the model's domain check (:meth:`gaitml.models.domain.DomainModel.check`).

One window at a time, written straight from the definition in
:mod:`gaitml.models.domain`: standardise with the training mean and scale, the
Mahalanobis distance ``sqrt((z - m_c)^T P_c (z - m_c))`` to every class with the
stored precision ``P_c`` (no Cholesky factors), the smallest; the angle
``arccos(g . u)`` to every kept training gravity direction ``u``, the smallest. A
window with a non-finite feature has distance inf, a non-finite gravity vector
angle NaN (out of domain). It exists to check the vectorised and the one-window
paths (tests/domain/test_one_window.py); not for production use.
"""

from __future__ import annotations

import numpy as np

__all__ = ["reference_check", "stacked_distances", "stacked_dynamics_distances", "dynamics_distances_loop", "span_median_loop"]


def reference_check(dom, X, gravity=None) -> dict[str, np.ndarray]:
    """``dom.check(X, gravity)`` computed window by window with the quadratic forms of the stored precisions."""
    X = np.asarray(X, dtype=float).reshape(-1, len(dom.feature_names))
    a = dom.arrays
    dist = np.empty(len(X))
    ang = np.full(len(X), np.nan)
    G = None if gravity is None else np.asarray(gravity, dtype=float).reshape(-1, 3)
    for i, x in enumerate(X):
        if not np.isfinite(x).all():
            dist[i] = np.inf
        else:
            z = (x - a["center"]) / a["scale"]
            quad = [float((z - m) @ P @ (z - m)) for m, P in zip(a["class_means"], a["class_precisions"], strict=True)]
            dist[i] = np.sqrt(max(min(quad), 0.0))
        if dom.gravity_check and len(a["gravity_dirs"]) and np.isfinite(G[i]).all():
            ang[i] = min(float(np.arccos(np.clip(u @ G[i], -1.0, 1.0))) for u in a["gravity_dirs"])
    ok = dist <= dom.distance_threshold
    if dom.gravity_check:
        ok &= ang <= dom.gravity_threshold_rad  # NaN: out of domain
    return {"distance": dist, "gravity_angle_rad": ang, "in_domain": ok}


def stacked_distances(dom, X) -> np.ndarray:
    """The feature distance as :meth:`DomainModel.distances` computed it before the column blocks (issue 12 speed).

    Standardise, one product with the Cholesky factors of every class's precision
    side by side (``P_c = L_c L_c^T``, so ``(z - m_c)^T P_c (z - m_c) = |z L_c - m_c L_c|^2``),
    squares summed per class, the smallest, its root; inf for a row with a non-finite
    feature. Kept to check that the faster batch path computes the same numbers.
    """
    X = np.asarray(X, dtype=float).reshape(-1, len(dom.feature_names))
    a = dom.arrays
    chol = np.linalg.cholesky(a["class_precisions"])
    stacked = np.concatenate(list(chol), axis=1)
    offset = np.concatenate([m @ L for m, L in zip(a["class_means"], chol, strict=True)])
    finite = np.isfinite(X).all(axis=1)
    Z = (np.where(np.isfinite(X), X, 0.0) - a["center"]) / a["scale"]
    with np.errstate(invalid="ignore", over="ignore"):
        Y = (Z @ stacked - offset) ** 2
        d = np.sqrt(Y.reshape(len(Z), -1, X.shape[1]).sum(axis=2).min(axis=1))
    d[~finite] = np.inf
    return d


def dynamics_distances_loop(dom, Q) -> np.ndarray:
    """:meth:`DomainModel.dynamics_distances` window by window: the quadratic forms of the stored dynamics precisions.

    Standardise with ``dyn_center`` / ``dyn_scale``, ``sqrt((z - m_g)^T P_g (z - m_g))`` to every
    (mode, position) Gaussian, the smallest; inf for a row with a non-finite descriptor.
    """
    a = dom.arrays
    Q = np.asarray(Q, dtype=float).reshape(-1, len(a["dyn_center"]))
    out = np.empty(len(Q))
    for i, q in enumerate(Q):
        if not np.isfinite(q).all():
            out[i] = np.inf
            continue
        z = (q - a["dyn_center"]) / a["dyn_scale"]
        quad = [float((z - m) @ P @ (z - m)) for m, P in zip(a["dyn_means"], a["dyn_precisions"], strict=True)]
        out[i] = np.sqrt(max(min(quad), 0.0))
    return out


def stacked_dynamics_distances(dom, Q) -> np.ndarray:
    """The dynamics distance as :meth:`DomainModel.dynamics_distances` computed it before the standardisation was folded
    into its product (issue 12 speed): standardise, one product with the stacked Cholesky factors, subtract
    ``m_g L_g``, squares summed per Gaussian, the smallest, its root; inf for a non-finite row.
    """
    a = dom.arrays
    Q = np.asarray(Q, dtype=float).reshape(-1, len(a["dyn_center"]))
    chol = np.linalg.cholesky(a["dyn_precisions"])
    stacked = np.concatenate(list(chol), axis=1)
    offset = np.concatenate([m @ L for m, L in zip(a["dyn_means"], chol, strict=True)])
    finite = np.isfinite(Q).all(axis=1)
    Z = (np.where(finite[:, None], Q, 0.0) - a["dyn_center"]) / a["dyn_scale"]
    Y = (Z @ stacked - offset) ** 2
    d = np.sqrt(Y.reshape(len(Q), -1, Q.shape[1]).sum(axis=2).min(axis=1))
    d[~finite] = np.inf
    return d


def span_median_loop(per_window, span: int, every: int = 1) -> np.ndarray:
    """The dynamics decision statistic of every window of one recording, one window at a time.

    ``per_window`` (k,) holds the window distance of the computed windows (rows 0, every,
    2 every, ...; the other rows are not read). Window i takes ``np.nanmedian`` of the
    computed windows among rows ``i - span + 1 .. i``; NaN when there is none.
    """
    per_window = np.asarray(per_window, dtype=float).reshape(-1)
    out = np.full(len(per_window), np.nan)
    for i in range(len(per_window)):
        vals = [per_window[j] for j in range(max(0, i - span + 1), i + 1) if j % every == 0]
        vals = [v for v in vals if not np.isnan(v)]
        if vals:
            out[i] = float(np.median(np.asarray(vals)))
    return out
