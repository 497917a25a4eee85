"""The training domain of a model, and whether a new window lies inside it.

A classifier has no "unknown" class: a window unlike anything it was trained on (a
phone in a pocket for a model trained on hand-held phones, a foot-mounted IMU, a
recording in g read as m/s^2) still gets one of its modes, often confidently. The
domain record lets ``gaitml predict`` and ``gaitml pdr`` say so, window by window.

What is recorded at training time (``model.json`` key ``domain``; the arrays in
``arrays.npz`` under names starting ``domain__``, read with ``allow_pickle=False``):

- **positions**: the carrying positions of the training recordings (recording meta
  ``position``, ``"unknown"`` where absent) with their window counts.
- **feature distance**: the features are standardised with the training mean and
  standard deviation; each training class gets a Gaussian (class mean and a
  Ledoit-Wolf shrunk covariance, which stays invertible with the 104 strongly
  correlated features). The distance of a window is its smallest Mahalanobis distance
  to the classes: small when it looks like *some* trained mode.
- **gravity direction** (phone-frame models only): the unit vector of the window mean
  of the acceleration in the phone frame. A set of up to ``MAX_GRAVITY_DIRECTIONS``
  training directions is kept (the distribution, which may have several modes:
  flat and tilted phones); the angle of a window's direction to the nearest of
  them is its gravity distance. Its mean direction and the quantiles of the angle to
  it summarise the distribution for the model card. A gravity-frame model's features
  do not depend on the phone's orientation, so its gravity direction is recorded but
  not checked.
- **thresholds**: the ``quantile`` (default 0.99) of the distances of training
  windows *held out*: the training groups (subjects) are split into up to 5 folds;
  the standardisation, class Gaussians and gravity set are fitted on the other folds
  and the distances measured on the held-out one. A threshold from the in-sample
  distances would be optimistic (every training window is near its own Gaussian); it
  is recorded next to the held-out one for comparison.

A window is **in domain** when its feature distance is at most the distance threshold
and (phone frame) its gravity angle is at most the gravity threshold. By construction
about 1 - quantile of new windows from the training distribution (new subjects) fall
outside each test; the domain report (``experiments/reports/model-domain.md``) measures
it on new simulated subjects and on real recordings.

This is ours (the papers have no domain check); it detects *that* a window is unlike the
training data, not *why*.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from gaitml.errors import ModelError

__all__ = [
    "DOMAIN_VERSION",
    "DomainModel",
    "fit_domain",
    "window_gravity",
    "domain_from_model_info",
    "NO_DOMAIN_WARNING",
    "OUT_OF_DOMAIN_WARN_FRACTION",
    "domain_warning",
    "out_of_domain_fraction",
]

DOMAIN_VERSION = 1
#: Prefix of the domain arrays inside ``arrays.npz``.
ARRAY_PREFIX = "domain__"
#: At most this many training gravity directions are kept (a random subset).
MAX_GRAVITY_DIRECTIONS = 400
#: Default quantile of the held-out distances used as thresholds.
DEFAULT_QUANTILE = 0.99
#: Folds over the training groups for the held-out thresholds.
HELDOUT_FOLDS = 5
#: ``gaitml predict`` / ``pdr`` print one warning when more than this fraction of windows is out of domain.
OUT_OF_DOMAIN_WARN_FRACTION = 0.10
#: The warning for a model saved without a domain record.
NO_DOMAIN_WARNING = (
    "the model has no domain record (trained before gaitml recorded one), so in_domain is unknown (null); "
    "retrain it with 'gaitml train CONFIG' to get the out-of-domain check"
)
_ARRAYS = ("center", "scale", "class_means", "class_precisions", "gravity_dirs", "feature_lo", "feature_hi")


def window_gravity(acc, starts, length: int) -> np.ndarray:
    """Unit vector of the mean acceleration of every window (phone frame), shape (k, 3).

    Windows whose mean is (nearly) zero (free fall) have no direction: NaN rows.
    """
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    return span_gravity(acc, starts, starts + int(length))


def span_gravity(acc, starts, ends) -> np.ndarray:
    """:func:`window_gravity` of windows of different lengths (``[start, end)`` spans, e.g. step windows)."""
    acc = np.asarray(acc, dtype=float)
    starts = np.asarray(starts, dtype=np.int64).reshape(-1)
    ends = np.asarray(ends, dtype=np.int64).reshape(-1)
    cum = np.zeros((len(acc) + 1, 3))
    np.cumsum(acc, axis=0, out=cum[1:])
    length = np.maximum(ends - starts, 1).astype(float)
    mean = (cum[ends] - cum[starts]) / length[:, None]
    norm = np.linalg.norm(mean, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = mean / norm[:, None]
    out[~(norm > 1e-6)] = np.nan
    return out


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
        precs[i] = lw.precision_
    return means, precs


def _min_mahalanobis(Z: np.ndarray, means: np.ndarray, precs: np.ndarray) -> np.ndarray:
    best = np.full(len(Z), np.inf)
    for m, P in zip(means, precs, strict=True):
        d = Z - m
        q = np.einsum("ij,ij->i", d @ P, d)
        best = np.minimum(best, np.sqrt(np.maximum(q, 0.0)))
    return best


def _nearest_angle(g: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """Angle (rad) from each row of ``g`` to the nearest of ``dirs``; NaN rows give NaN."""
    if len(dirs) == 0:
        return np.full(len(g), np.nan)
    if not len(g):
        return np.zeros(0)
    bad = ~np.isfinite(g).all(axis=1)
    any_bad = bad.any()
    cos = ((np.where(bad[:, None], 0.0, g) if any_bad else g) @ dirs.T).max(axis=1)
    out = np.arccos(np.clip(cos, -1.0, 1.0))
    if any_bad:
        out[bad] = np.nan
    return out


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


def _subsample_dirs(g: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    g = g[np.all(np.isfinite(g), axis=1)]
    if len(g) > MAX_GRAVITY_DIRECTIONS:
        g = g[np.sort(rng.choice(len(g), MAX_GRAVITY_DIRECTIONS, replace=False))]
    return g


@dataclasses.dataclass
class DomainModel:
    """The training domain of a model (see the module docstring).

    Attributes
    ----------
    feature_set, frame : str
        Features the distance is computed on (a feature model's own; ``all52`` /
        ``all52+gyro`` for raw-input models) and their frame.
    feature_names : list of str
    classes : list of str
    positions : dict
        Carrying position -> number of training windows.
    quantile : float
        Quantile of the held-out distances used as thresholds.
    distance_threshold : float
        Largest in-domain feature distance (held out); ``distance_threshold_in_sample`` for comparison.
    gravity_check : bool
        Whether the gravity direction is checked (phone frame only).
    gravity_threshold_rad : float
        Largest in-domain angle to the nearest training gravity direction (held out).
    arrays : dict of ndarray
        ``center``, ``scale`` (standardisation), ``class_means`` (c, p),
        ``class_precisions`` (c, p, p), ``gravity_dirs`` (m, 3), ``feature_lo``,
        ``feature_hi`` (0.5 % and 99.5 % training quantiles per feature, raw units).
    summary : dict
        JSON-ready numbers for the model card (gravity mean and angle quantiles,
        held-out scheme, window counts, in-sample thresholds).
    """

    feature_set: str
    frame: str
    feature_names: list[str]
    classes: list[str]
    positions: dict
    quantile: float
    distance_threshold: float
    distance_threshold_in_sample: float
    gravity_check: bool
    gravity_threshold_rad: float
    gravity_threshold_in_sample_rad: float
    arrays: dict
    summary: dict = dataclasses.field(default_factory=dict)

    # ---- persistence (JSON + plain arrays; no pickle)
    def to_json(self) -> dict:
        """The ``domain`` entry of ``model.json`` (the arrays go to ``arrays.npz``)."""
        return {
            "version": DOMAIN_VERSION,
            "feature_set": self.feature_set,
            "frame": self.frame,
            "feature_names": list(self.feature_names),
            "classes": list(self.classes),
            "positions": {str(k): int(v) for k, v in self.positions.items()},
            "quantile": float(self.quantile),
            "distance_threshold": float(self.distance_threshold),
            "distance_threshold_in_sample": float(self.distance_threshold_in_sample),
            "gravity_check": bool(self.gravity_check),
            "gravity_threshold_rad": float(self.gravity_threshold_rad),
            "gravity_threshold_in_sample_rad": float(self.gravity_threshold_in_sample_rad),
            "arrays": [ARRAY_PREFIX + k for k in _ARRAYS],
            "summary": self.summary,
        }

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The arrays to store in ``arrays.npz`` (names prefixed ``domain__``)."""
        return {ARRAY_PREFIX + k: np.asarray(self.arrays[k], dtype=float) for k in _ARRAYS}

    @classmethod
    def from_json(cls, info: dict, arrays: dict[str, np.ndarray]) -> DomainModel:
        """Rebuild from the ``domain`` entry and the ``domain__`` arrays; ModelError when they do not fit."""
        try:
            if int(info["version"]) != DOMAIN_VERSION:
                raise ModelError(f"domain record version {info['version']} is not {DOMAIN_VERSION}; retrain the model with this gaitml.")
            arr = {k: np.asarray(arrays[ARRAY_PREFIX + k], dtype=float) for k in _ARRAYS}
            names = [str(n) for n in info["feature_names"]]
            classes = [str(c) for c in info["classes"]]
            p, c = len(names), len(classes)
            shapes = {
                "center": (p,),
                "scale": (p,),
                "feature_lo": (p,),
                "feature_hi": (p,),
                "class_means": (c, p),
                "class_precisions": (c, p, p),
            }
            for k, shp in shapes.items():
                if arr[k].shape != shp:
                    raise ValueError(f"{k} has shape {arr[k].shape}, expected {shp}")
            if arr["gravity_dirs"].ndim != 2 or arr["gravity_dirs"].shape[1] != 3:
                raise ValueError(f"gravity_dirs has shape {arr['gravity_dirs'].shape}, expected (m, 3)")
            return cls(
                feature_set=str(info["feature_set"]),
                frame=str(info["frame"]),
                feature_names=names,
                classes=classes,
                positions={str(k): int(v) for k, v in dict(info["positions"]).items()},
                quantile=float(info["quantile"]),
                distance_threshold=float(info["distance_threshold"]),
                distance_threshold_in_sample=float(info["distance_threshold_in_sample"]),
                gravity_check=bool(info["gravity_check"]),
                gravity_threshold_rad=float(info["gravity_threshold_rad"]),
                gravity_threshold_in_sample_rad=float(info["gravity_threshold_in_sample_rad"]),
                arrays=arr,
                summary=dict(info.get("summary") or {}),
            )
        except ModelError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(
                f"the model's domain record does not fit its arrays ({type(exc).__name__}: {' '.join(str(exc).split())[:160]}); "
                "retrain the model (gaitml train CONFIG)."
            ) from exc

    # ---- the check
    def _factors(self) -> tuple[np.ndarray, np.ndarray]:
        """Stacked Cholesky factors ``[L_1 .. L_c]`` (p, c p) of the precisions and ``m_c L_c`` (c p,), cached.

        ``(z - m_c)^T P_c (z - m_c) = |z L_c - m_c L_c|^2`` with ``P_c = L_c L_c^T``: one
        matrix product serves every class.
        """
        cache = getattr(self, "_factor_cache", None)
        if cache is None:
            precs, means = self.arrays["class_precisions"], self.arrays["class_means"]
            try:
                chol = np.linalg.cholesky(precs)  # (c, p, p)
            except np.linalg.LinAlgError as exc:
                raise ModelError("the domain record's precision matrices are not positive definite; retrain the model.") from exc
            stacked = np.ascontiguousarray(np.concatenate(list(chol), axis=1))
            offset = np.concatenate([m @ c for m, c in zip(means, chol, strict=True)])
            cache = (stacked, offset)
            object.__setattr__(self, "_factor_cache", cache)
        return cache

    def distances(self, X) -> np.ndarray:
        """Feature distance of every row of ``X`` (raw feature units, columns ``feature_names``)."""
        X = np.asarray(X, dtype=float)
        if X.ndim != 2 or X.shape[1] != len(self.feature_names):
            raise ModelError(f"the domain check takes {len(self.feature_names)} features, got shape {X.shape}; retrain the model.")
        if not len(X):
            return np.zeros(0)
        finite = np.isfinite(X).all(axis=1)
        all_finite = bool(finite.all())
        stacked, offset = self._factors()
        # plain array operations (no nan_to_num, no einsum): a one-window call (streaming) costs tens of
        # microseconds, not hundreds (benchmarks/models.py stream-domain-check-per-window); rows with a
        # non-finite feature are out of domain (distance inf) whatever their other features
        Z = ((X if all_finite else np.where(np.isfinite(X), X, 0.0)) - self.arrays["center"]) / self.arrays["scale"]
        with np.errstate(invalid="ignore", over="ignore"):
            Y = (Z @ stacked - offset).reshape(len(Z), -1, X.shape[1])
            d = np.sqrt((Y * Y).sum(axis=2).min(axis=1))
        if not all_finite:
            d[~finite] = np.inf
        return d

    def gravity_angles(self, gravity) -> np.ndarray:
        """Angle (rad) of each gravity unit vector (rows, phone frame) to the nearest training direction."""
        return _nearest_angle(np.asarray(gravity, dtype=float).reshape(-1, 3), self.arrays["gravity_dirs"])

    def check(self, X, gravity=None) -> dict[str, np.ndarray]:
        """In-domain flags of windows.

        Parameters
        ----------
        X : (k, p) features of the windows (``feature_names`` order, raw units).
        gravity : (k, 3) window gravity unit vectors (:func:`window_gravity`), optional;
            needed when ``gravity_check`` is on.

        Returns
        -------
        dict with ``distance`` (k,), ``gravity_angle_rad`` (k,; NaN when not checked)
        and ``in_domain`` (k,) bool.
        """
        X = np.asarray(X, dtype=float)
        if X.shape == (1, len(self.feature_names)):  # one window (streaming): the short path when it applies
            one = self._check_one(X, gravity)
            if one is not None:
                return one
        d = self.distances(X)
        ok = d <= self.distance_threshold
        if not self.gravity_check:
            return {"distance": d, "gravity_angle_rad": np.full(len(d), np.nan), "in_domain": ok}
        if gravity is None:
            raise ModelError("this model's domain checks the gravity direction; pass the window gravity (window_gravity).")
        ang = self.gravity_angles(gravity)
        ok &= ang <= self.gravity_threshold_rad  # a NaN angle (no gravity direction) compares False: out of domain
        return {"distance": d, "gravity_angle_rad": ang, "in_domain": ok}

    def _one_window(self) -> tuple:
        """What the one-window check needs beyond the stored arrays, computed at its first call and cached.

        ``(stacked, offset, n_classes, center, scale, gravity_dirs.T, feature_bound, gravity_bound)``
        (:meth:`_factors`, :func:`_feature_bound`, :func:`_gravity_bound`).
        """
        cache = self.__dict__.get("_one_window_cache")
        if cache is None:
            stacked, offset = self._factors()
            a = self.arrays
            cache = (
                stacked,
                offset,
                len(self.classes),
                a["center"],
                a["scale"],
                a["gravity_dirs"].T,
                _feature_bound(a["center"], a["scale"], stacked, offset),
                _gravity_bound(a["gravity_dirs"]),
            )
            object.__setattr__(self, "_one_window_cache", cache)
        return cache

    def _check_one(self, X: np.ndarray, gravity) -> dict[str, np.ndarray] | None:
        """:meth:`check` of one window ``X`` (1, p) (streaming), or None when the general path must answer.

        The same arithmetic as :meth:`distances` and :func:`_nearest_angle` on one row
        (standardise, one product with the stacked factors, squared norms per class,
        min, sqrt; the largest cosine to the kept gravity directions, clipped, arccos),
        so the same numbers bit for bit, with a dozen array operations instead of about
        thirty (each costs about a microsecond whatever its size, which is what a
        one-window call spends its time on): the non-finite masks and ``np.errstate``
        give way to one test of the input magnitudes against bounds computed once
        (:func:`_feature_bound`, :func:`_gravity_bound`: under them nothing can overflow
        or be invalid, so nothing needs silencing). Anything else (a non-finite or huge
        input, no kept direction, gravity of another shape) returns None and goes the
        general way, which handles it as before.
        """
        stacked, offset, n_classes, center, scale, dirs_t, x_bound, g_bound = self.__dict__.get("_one_window_cache") or self._one_window()
        if self.gravity_check:
            if gravity is None:
                return None
            g = np.asarray(gravity, dtype=float)
            if g.size != 3 or not max(map(abs, g.ravel().tolist())) <= g_bound:  # inf, huge (a NaN may pass: caught below)
                return None
        if x_bound < 0 or not np.maximum.reduce(np.abs(X), axis=None) <= x_bound:  # inf, huge, NaN (compares False)
            return None
        Y = (X - center) / scale @ stacked
        Y -= offset
        Y *= Y
        sq = np.add.reduce(Y.reshape(n_classes, -1), axis=1).tolist()  # squared distance to every class (ndarray.sum without its wrapper)
        d = math.sqrt(min(sq))  # correctly rounded, as np.sqrt
        ok = d <= self.distance_threshold
        if not self.gravity_check:
            return {"distance": np.array([d]), "gravity_angle_rad": np.array([np.nan]), "in_domain": np.array([ok])}
        cos = float(np.maximum.reduce(g.reshape(1, 3) @ dirs_t, axis=None))  # ndarray.max without its wrapper
        if math.isnan(cos):
            return None
        ang = float(np.arccos(min(max(cos, -1.0), 1.0)))  # np.clip of a number
        return {
            "distance": np.array([d]),
            "gravity_angle_rad": np.array([ang]),
            "in_domain": np.array([ok and ang <= self.gravity_threshold_rad]),
        }


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
) -> DomainModel:
    """Fit the domain record of a training set (see the module docstring).

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
    """
    from sklearn.model_selection import GroupKFold

    X = np.asarray(X, dtype=float)
    y = np.asarray(y).astype(str)
    groups = np.asarray(groups).astype(str)
    gravity = np.asarray(gravity, dtype=float).reshape(-1, 3)
    n = len(X)
    if not (len(y) == len(groups) == len(gravity) == n) or n < 2:
        raise ModelError(f"fit_domain needs matching rows (X {n}, y {len(y)}, groups {len(groups)}, gravity {len(gravity)}), at least 2.")
    if not 0.5 <= float(quantile) < 1.0:
        raise ModelError(f"domain quantile must be in [0.5, 1), got {quantile}.")
    rng = np.random.default_rng(seed)
    classes = sorted({str(c) for c in y})
    gravity_check = frame == "phone"
    ug = np.unique(groups)
    k = min(HELDOUT_FOLDS, len(ug))
    held_d = np.full(n, np.nan)
    held_a = np.full(n, np.nan)
    if k >= 2:
        for tr, te in GroupKFold(n_splits=k).split(X, y, groups):
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
    pos = np.full(n, "unknown", dtype=object) if positions is None else np.asarray(positions).astype(str)
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
            "feature_lo": np.quantile(X, 0.005, axis=0),
            "feature_hi": np.quantile(X, 0.995, axis=0),
        },
        summary=summary,
    )


def domain_from_model_info(info: dict, arrays: dict[str, np.ndarray]) -> DomainModel | None:
    """The model's :class:`DomainModel`, or None for a model saved without one."""
    dom: Any = info.get("domain")
    if dom is None:
        return None
    if not isinstance(dom, dict):
        raise ModelError("the model's domain entry in model.json is not an object; retrain the model (gaitml train CONFIG).")
    return DomainModel.from_json(dom, arrays)


def out_of_domain_fraction(in_domain) -> float | None:
    """Fraction of windows flagged out of domain; None when unknown (no domain record) or no windows."""
    flags = [v for v in np.asarray(in_domain, dtype=object).reshape(-1) if v is not None]
    if not flags:
        return None
    return float(np.mean([not bool(v) for v in flags]))


def domain_warning(model, in_domain, what: str = "windows") -> str | None:
    """The one warning line (without the ``gaitml: warning:`` prefix) for a prediction, or None.

    A model without a domain record gives :data:`NO_DOMAIN_WARNING`; otherwise a
    warning is given when more than :data:`OUT_OF_DOMAIN_WARN_FRACTION` of the
    ``what`` are out of domain.
    """
    dom = getattr(model, "domain", None)
    if dom is None:
        return NO_DOMAIN_WARNING
    frac = out_of_domain_fraction(in_domain)
    if frac is None or frac <= OUT_OF_DOMAIN_WARN_FRACTION:
        return None
    n = len(np.asarray(in_domain, dtype=object).reshape(-1))
    k = int(round(frac * n))
    positions = ", ".join(sorted(dom.positions)) or "unknown"
    return (
        f"{100 * frac:.1f} % of the {what} ({k} of {n}) lie outside the model's training domain (positions {positions}, "
        f"{dom.frame} frame); their modes are unreliable: use a model trained on recordings like this one "
        "(README: 'Is my recording in the model's domain?')"
    )
