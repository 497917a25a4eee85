"""The domain record of a trained model: its persistence and the per-window check.

:class:`DomainModel` holds what :class:`~gaitml.models.domain.DomainCheck` learned
(thresholds, class Gaussians, gravity directions, the optional dynamics part), writes it
as a JSON entry plus plain arrays (no pickle) and checks windows against it.

The feature distance has a plain reference (:func:`~gaitml.models.domain._distance._min_mahalanobis`,
one class at a time) and the check computes the same quadratic forms faster: a batch
takes column blocks of the stacked Cholesky factors in float32 and recomputes in float64
every window whose flag could differ (:meth:`DomainModel._certified_distances`); one
window (a stream) takes one product with the stacked factors (:meth:`DomainModel._check_one`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, NamedTuple

import numpy as np

from gaitml.errors import ModelError
from gaitml.models.domain._descriptors import DYNAMICS_NAMES, dynamics_sample_step
from gaitml.models.domain._distance import _feature_bound, _gravity_bound, _min_mahalanobis
from gaitml.models.domain._gravity import _nearest_angle
from gaitml.models.domain._running import running_median
from gaitml.parallel import one_blas_thread
from gaitml.recording.timestamps import RATE_TOLERANCE

__all__ = [
    "ARRAY_PREFIX",
    "DOMAIN_VERSION",
    "RATE_TOLERANCE",
    "ChunkContext",
    "DomainModel",
    "domain_from_model_info",
    "domain_rate_reason",
    "out_of_domain_fraction",
]

DOMAIN_VERSION = 1
#: Prefix of the domain arrays inside ``arrays.npz``.
ARRAY_PREFIX = "domain__"
#: The arrays of the record (records written before may also carry ``feature_lo`` / ``feature_hi``, which are not read).
_ARRAYS = ("center", "scale", "class_means", "class_precisions", "gravity_dirs")
#: The batch feature distance (:meth:`DomainModel.distances` of at least ``_BLOCKED_MIN_ROWS`` rows) multiplies by the
#: Cholesky factors in column blocks of about this many columns, skipping the zeros above their diagonal
#: (the choice is measured in ``benchmarks/README.md``).
_DISTANCE_BLOCK_COLUMNS = 13
#: Fewer rows (a stream's one window) take one product with the whole stacked factors: fewer calls.
_BLOCKED_MIN_ROWS = 64
#: The arrays of the optional orientation-dynamics part.
_DYN_ARRAYS = ("dyn_center", "dyn_scale", "dyn_means", "dyn_precisions")


class ChunkContext(NamedTuple):
    """What a chunked computation must keep around each chunk for the check to give the whole file's answer.

    ``left_windows``: windows of context before a chunk's first kept window (the
    dynamics span median reads the last ``span`` windows); ``sample_step``: chunk
    offsets must be multiples of it (the descriptors keep every ``sample_step``-th
    sample); ``window_step``: a chunk must start on a computed window (every
    ``window_step``-th window's dynamics is computed).
    """

    left_windows: int
    sample_step: int
    window_step: int


@dataclasses.dataclass
class DomainModel:
    """The training domain of a model (see :mod:`gaitml.models.domain`).

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
        ``class_precisions`` (c, p, p), ``gravity_dirs`` (m, 3).
    summary : dict
        JSON-ready numbers for the model card (gravity mean and angle quantiles,
        held-out scheme, window counts, in-sample thresholds).
    dynamics : dict or None
        The orientation-dynamics part (None in records without it): ``labels`` (the
        ``mode|position`` of each Gaussian), ``span`` (windows), ``every`` (the check
        computes every ``every``-th window's dynamics, :data:`DYNAMICS_EVERY`; 1 in records
        written before it), ``threshold`` (largest in-domain span median of the dynamics
        distance, held out) and ``threshold_in_sample``; its arrays ``dyn_center``, ``dyn_scale`` (13,),
        ``dyn_means`` (g, 13), ``dyn_precisions`` (g, 13, 13) are in ``arrays``.
    min_rate_hz : float or None
        The lowest sampling rate the model was trained at (Hz; the information rate of its
        training recordings, :func:`gaitml.pipeline.runner.training_min_rate`): a recording made
        below :data:`RATE_TOLERANCE` times it is out of domain (:func:`domain_rate_reason`). None in
        records written before it: the rate is not checked.
    acc_range_ms2 : float or None
        The accelerometer range (m/s^2 per axis) the record reads every recording through,
        in its fit and in :func:`gaitml.models.predict_recording`, when the record alone has
        one (``[train] domain_acc_range_ms2``; the classifier then reads the recording as it
        comes): the features, gravity direction and orientation dynamics of the check are
        computed on the accelerometer clipped to +-``acc_range_ms2``
        (:func:`gaitml.features.clip_acc`), so a phone that reads beyond the narrowest
        range in the training data is compared with training windows on what every training
        phone could report. None (records without the key): the recording as the model reads it.
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
    dynamics: dict | None = None
    min_rate_hz: float | None = None
    acc_range_ms2: float | None = None

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
            "arrays": [ARRAY_PREFIX + k for k in self._array_names()],
            "summary": self.summary,
            **({"dynamics": dict(self.dynamics)} if self.dynamics is not None else {}),
            **({"min_rate_hz": float(self.min_rate_hz)} if self.min_rate_hz is not None else {}),
            **({"acc_range_ms2": float(self.acc_range_ms2)} if self.acc_range_ms2 is not None else {}),
        }

    def _array_names(self) -> tuple[str, ...]:
        return _ARRAYS + (_DYN_ARRAYS if self.dynamics is not None else ())

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The arrays to store in ``arrays.npz`` (names prefixed ``domain__``)."""
        return {ARRAY_PREFIX + k: np.asarray(self.arrays[k], dtype=float) for k in self._array_names()}

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
                "class_means": (c, p),
                "class_precisions": (c, p, p),
            }
            for k, shp in shapes.items():
                if arr[k].shape != shp:
                    raise ValueError(f"{k} has shape {arr[k].shape}, expected {shp}")
            if arr["gravity_dirs"].ndim != 2 or arr["gravity_dirs"].shape[1] != 3:
                raise ValueError(f"gravity_dirs has shape {arr['gravity_dirs'].shape}, expected (m, 3)")
            dyn = info.get("dynamics")
            if dyn is not None:  # the optional orientation-dynamics part (records without it check as before)
                dyn = {
                    "labels": [str(v) for v in dyn["labels"]],
                    "span": int(dyn["span"]),
                    # records written before the grid was fitted on every window: checked on every window
                    "every": int(dyn.get("every", 1)),
                    "threshold": float(dyn["threshold"]),
                    "threshold_in_sample": float(dyn["threshold_in_sample"]),
                }
                arr.update({k: np.asarray(arrays[ARRAY_PREFIX + k], dtype=float) for k in _DYN_ARRAYS})
                q, g = len(DYNAMICS_NAMES), len(dyn["labels"])
                for k, shp in {"dyn_center": (q,), "dyn_scale": (q,), "dyn_means": (g, q), "dyn_precisions": (g, q, q)}.items():
                    if arr[k].shape != shp:
                        raise ValueError(f"{k} has shape {arr[k].shape}, expected {shp}")
                if dyn["span"] < 1:
                    raise ValueError(f"dynamics span {dyn['span']} is below 1")
                if dyn["every"] < 1 or dyn["span"] % dyn["every"]:
                    raise ValueError(f"dynamics grid step {dyn['every']} does not divide the span {dyn['span']}")
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
                dynamics=dyn,
                # records written before the rate was kept: None, the rate is not checked
                min_rate_hz=None if info.get("min_rate_hz") is None else float(info["min_rate_hz"]),
                acc_range_ms2=_record_range(info.get("acc_range_ms2")),
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
        """Feature distance of every row of ``X`` (raw feature units, columns ``feature_names``).

        From :data:`_BLOCKED_MIN_ROWS` rows on, the distances are float32-accurate (about
        1e-7 relative) except within a rounding-error bound of ``distance_threshold``,
        where they are float64: ``distance <= distance_threshold`` is the float64 decision
        on every row (:meth:`_certified_distances`). Fewer rows (a stream's one window): float64.
        """
        X = np.asarray(X, dtype=float)
        if X.ndim != 2 or X.shape[1] != len(self.feature_names):
            raise ModelError(f"the domain check takes {len(self.feature_names)} features, got shape {X.shape}; retrain the model.")
        if not len(X):
            return np.zeros(0)
        finite = np.isfinite(X).all(axis=1)
        all_finite = bool(finite.all())
        # plain array operations (no nan_to_num, no einsum): a one-window call (streaming) costs tens of
        # microseconds, not hundreds (benchmarks/models.py stream-domain-check-per-window); rows with a
        # non-finite feature are out of domain (distance inf) whatever their other features
        Xf = X if all_finite else np.where(np.isfinite(X), X, 0.0)
        d = self._certified_distances(Xf) if len(X) >= _BLOCKED_MIN_ROWS else None  # float32, exact where a flag is at stake
        if d is None:
            d = self._stacked_distances((Xf - self.arrays["center"]) / self.arrays["scale"])
        if not all_finite:
            d[~finite] = np.inf
        return d

    def _stacked_distances(self, Z: np.ndarray) -> np.ndarray:
        """Smallest Mahalanobis distance of standardised rows ``Z`` to the classes: one product with the stacked factors."""
        stacked, offset = self._factors()
        with np.errstate(invalid="ignore", over="ignore"):
            Y = Z @ stacked  # in place from here: the same arithmetic without two more (n, c p) temporaries
            Y -= offset
            Y *= Y
            return np.sqrt(Y.reshape(len(Z), -1, Z.shape[1]).sum(axis=2).min(axis=1))

    def _float32_blocks(self) -> tuple[list[tuple[int, int, np.ndarray]], float]:
        """The stacked factors of :meth:`_factors` in float32 column blocks without their zero rows, and the error scale; cached.

        ``L_c`` is lower triangular: its columns ``[j0, j1)`` are zero above row ``j0``. With
        ``F`` (p - j0, c (j1 - j0)) the rows ``j0:`` of those columns of every class and ``o``
        the matching entries of the offsets ``m_c L_c``, a block's entries of ``z L - m L``
        for a standardised row ``z`` are ``[z_j0.., 1] B`` with ``B = [F; -o]``. Per block
        ``(j0, j1, B^T)`` in float32 (the blocks hold about ``_DISTANCE_BLOCK_COLUMNS``
        columns), and ``max_c ||[L_c; -m_c L_c]||_F``, the largest Frobenius norm of a
        class's augmented factor, which bounds the float32 error (:meth:`_certified_distances`).
        """
        cache = self.__dict__.get("_f32_cache")
        if cache is None:
            stacked, offset = self._factors()
            p = len(self.feature_names)
            c = len(offset) // p
            per_class = stacked.reshape(p, c, p)  # [row, class, column]
            edges = np.linspace(0, p, max(1, round(p / _DISTANCE_BLOCK_COLUMNS)) + 1).round().astype(int)
            blocks = []
            for j0, j1 in zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True):
                F = per_class[j0:, :, j0:j1].reshape(p - j0, c * (j1 - j0))
                o = offset.reshape(c, p)[:, j0:j1].reshape(-1)
                blocks.append((j0, j1, np.ascontiguousarray(np.concatenate([F, -o[None, :]], axis=0).T, dtype=np.float32)))
            norm = float(np.sqrt(np.max((per_class * per_class).sum(axis=(0, 2)) + (offset.reshape(c, p) ** 2).sum(axis=1))))
            cache = (blocks, norm)
            object.__setattr__(self, "_f32_cache", cache)
        return cache

    def _certified_distances(self, X: np.ndarray) -> np.ndarray | None:
        """Feature distances of raw finite rows ``X`` in float32, recomputed in float64 wherever the flag could differ; or None.

        The column-block products of :meth:`_float32_blocks` on the rows standardised in
        float64. A float32 distance ``d~`` differs from the exact one by at most
        ``eps = 2 (gamma + 2u) (N ||z_aug|| + d~)`` with ``u = 2^-24``, ``gamma = (p + 3) u /
        (1 - (p + 3) u)`` (Higham's bound for a sum of ``p + 1`` products), ``N`` the
        largest Frobenius norm of a class's augmented factor (:meth:`_float32_blocks`) and
        ``z_aug = [z, 1]``: the rounding of the inputs, of every product's sums (entry by
        entry at most ``gamma |B|^T |z_aug|``, whose norm Cauchy-Schwarz bounds by
        ``N ||z_aug||``) and of the sum of the squares, with a factor 2 to spare. Every
        window whose ``d~`` lies within its ``eps`` of the distance threshold (or is not
        finite) is recomputed in float64 by the plain reference
        (:func:`~gaitml.models.domain._distance._min_mahalanobis`): the flags
        ``distance <= threshold`` are those of the float64 distances, by construction; the
        other distances are float32-accurate (about 1e-7 relative). None when a float64
        recomputation is not finite (an input so large that a sum overflows): the caller
        then takes the one product.
        """
        n, p = X.shape
        blocks, norm = self._float32_blocks()
        c = len(blocks[0][2]) // (blocks[0][1] - blocks[0][0])
        Z = (X - self.arrays["center"]) / self.arrays["scale"]
        ZT = np.empty((p + 1, n), dtype=np.float32)  # standardised features x windows and a row of ones (the offsets)
        ZT[:p] = Z.T
        ZT[p] = 1.0
        sq = np.zeros((c, n), dtype=np.float32)
        with np.errstate(invalid="ignore", over="ignore"):
            for j0, j1, BT in blocks:
                Y = BT @ ZT[j0:]
                Y *= Y
                sq += Y.reshape(c, j1 - j0, n).sum(axis=1)
            d = np.sqrt(sq.min(axis=0), dtype=float)
            u = 2.0**-24
            gamma = (p + 3) * u / (1.0 - (p + 3) * u)
            eps = 2.0 * (gamma + 2.0 * u) * (norm * np.sqrt(np.add.reduce(Z * Z, axis=1) + 1.0) + d)
            exact = ~(np.abs(d - self.distance_threshold) > eps)  # near the threshold, or not finite (NaN compares False)
            if exact.any():
                d64 = _min_mahalanobis(Z[exact], self.arrays["class_means"], self.arrays["class_precisions"])
                if not np.isfinite(d64).all():
                    return None
                d[exact] = d64
        return d

    def gravity_angles(self, gravity) -> np.ndarray:
        """Angle (rad) of each gravity unit vector (rows, phone frame) to the nearest training direction."""
        return _nearest_angle(np.asarray(gravity, dtype=float).reshape(-1, 3), self.arrays["gravity_dirs"])

    @property
    def dynamics_every(self) -> int:
        """Every how many windows the check computes the orientation dynamics (1 without a dynamics part)."""
        return 1 if self.dynamics is None else int(self.dynamics.get("every", 1))

    def dynamics_rows(self, n: int) -> np.ndarray:
        """The windows (of ``n``, in time order) whose :func:`orientation_dynamics` :meth:`check` reads: 0, every, 2 every, ..."""
        return np.arange(0, max(0, int(n)), self.dynamics_every)

    def chunk_context(self, sampling_rate_hz: float) -> ChunkContext:
        """The context a chunked prediction needs at ``sampling_rate_hz`` (:class:`ChunkContext`; none without a dynamics part)."""
        if self.dynamics is None:
            return ChunkContext(0, 1, 1)
        return ChunkContext(int(self.dynamics.get("span", 1)) - 1, dynamics_sample_step(float(sampling_rate_hz)), self.dynamics_every)

    def dynamics_distances(self, dynamics) -> np.ndarray:
        """Window dynamics distance of every row of ``dynamics`` (:func:`orientation_dynamics`); inf for non-finite rows."""
        if self.dynamics is None:
            raise ModelError("this model's domain record has no orientation-dynamics part; retrain the model to get it.")
        Q = np.asarray(dynamics, dtype=float).reshape(-1, len(DYNAMICS_NAMES))
        if not len(Q):
            return np.zeros(0)
        finite = np.isfinite(Q).all(axis=1)
        all_finite = bool(finite.all())
        cache = self.__dict__.get("_dyn_cache")
        if cache is None:
            cache = self._dynamics_factors()
        A, g = cache
        q = Q.shape[1]
        Qa = np.empty((len(Q), q + 1))  # the descriptors and a column of ones (the offsets)
        Qa[:, :q] = Q if all_finite else np.where(finite[:, None], Q, 0.0)
        Qa[:, q] = 1.0
        with np.errstate(invalid="ignore", over="ignore"):
            Y = Qa @ A  # z L - m L of every Gaussian, standardised inside the product
            Y *= Y
            # squared distance to every Gaussian: sums over its q columns as one matrix-vector product, the smallest
            d = np.sqrt((Y.reshape(-1, q) @ np.ones(q)).reshape(len(Q), g).min(axis=1))
        if not all_finite:
            d[~finite] = np.inf
        d[np.isnan(d)] = np.inf  # an input so large that a sum overflows: out of domain
        return d

    def _dynamics_factors(self) -> tuple[np.ndarray, int]:
        """The stacked Cholesky factors of the dynamics Gaussians with the standardisation folded in, cached.

        With ``L_g`` the Cholesky factor of
        Gaussian g's precision (lower triangular) and ``m_g`` its mean, ``z L_g - m_g L_g``
        for descriptors ``x`` (``z = (x - dyn_center) / dyn_scale``) is ``[x, 1] A_g`` with
        ``A_g = [L_g / dyn_scale; -(m_g + dyn_center / dyn_scale) L_g]``. Returns ``([A_1 .. A_g], g)``
        ((q + 1, g q), one matrix product serves every Gaussian) and the number of Gaussians.
        """
        try:
            chol = np.linalg.cholesky(self.arrays["dyn_precisions"])
        except np.linalg.LinAlgError as exc:
            raise ModelError("the domain record's dynamics precision matrices are not positive definite; retrain the model.") from exc
        center, scale = self.arrays["dyn_center"], self.arrays["dyn_scale"]
        stacked = np.concatenate(list(chol), axis=1)
        offset = np.concatenate([m @ c for m, c in zip(self.arrays["dyn_means"], chol, strict=True)])
        A = np.ascontiguousarray(np.concatenate([stacked / scale[:, None], -(offset + (center / scale) @ stacked)[None, :]], axis=0))
        cache = (A, len(chol))
        object.__setattr__(self, "_dyn_cache", cache)
        return cache

    def check(self, X, gravity=None, dynamics=None) -> dict[str, np.ndarray]:
        """In-domain flags of windows.

        Parameters
        ----------
        X : (k, p) features of the windows (``feature_names`` order, raw units).
        gravity : (k, 3) window gravity unit vectors (:func:`window_gravity`), optional;
            needed when ``gravity_check`` is on.
        dynamics : :func:`orientation_dynamics` of the windows, **all of one recording in
            time order**: of the windows :meth:`dynamics_rows` names (0, every, 2 every,
            ...; what ``gaitml predict`` computes) or of all k windows (the others are
            not read). The decision uses the median of those windows' dynamics
            distances within the last ``dynamics["span"]`` windows (:func:`span_medians`);
            checked when the record has a dynamics part and this is given (``gaitml
            predict`` always gives it). Without it the dynamics part is not checked
            (one-window callers).

        Returns
        -------
        dict with ``distance`` (k,), ``gravity_angle_rad`` (k,; NaN when not checked),
        ``dynamics_distance`` (k,; the span median, NaN when not checked) and
        ``in_domain`` (k,) bool.
        """
        X = np.asarray(X, dtype=float)
        if X.shape == (1, len(self.feature_names)) and (dynamics is None or self.dynamics is None):
            # one window (streaming) without a dynamics test to make: the short path when it applies
            one = self._check_one(X, gravity)
            if one is not None:
                return one
        with one_blas_thread():  # the products of a batch: one BLAS thread (see one_blas_thread)
            return self._check_batch(X, gravity, dynamics)

    def _check_batch(self, X: np.ndarray, gravity, dynamics) -> dict[str, np.ndarray]:
        """:meth:`check` of any number of windows (the general path)."""
        d = self.distances(X)
        ok = d <= self.distance_threshold
        dyn = np.full(len(d), np.nan)
        if self.dynamics is not None and dynamics is not None:
            every = self.dynamics_every
            Q = np.asarray(dynamics, dtype=float).reshape(-1, len(DYNAMICS_NAMES))
            m = -(-len(d) // every)  # computed windows
            if len(Q) == len(d) and m != len(d):
                Q = Q[::every]  # every window given: the computed ones
            if len(Q) != m:
                raise ModelError(
                    f"the domain check got {len(d)} feature rows and {len(Q)} dynamics rows; pass one row per window "
                    f"or one per {every}-th window (DomainModel.dynamics_rows)."
                )
            # the median of the computed windows within each window's span: their running median, held (span_medians)
            dyn = running_median(self.dynamics_distances(Q), self.dynamics["span"] // every)[np.arange(len(d)) // every]
            ok &= dyn <= self.dynamics["threshold"]
        if not self.gravity_check:
            return {"distance": d, "gravity_angle_rad": np.full(len(d), np.nan), "dynamics_distance": dyn, "in_domain": ok}
        if gravity is None:
            raise ModelError("this model's domain checks the gravity direction; pass the window gravity (window_gravity).")
        ang = self.gravity_angles(gravity)
        ok &= ang <= self.gravity_threshold_rad  # a NaN angle (no gravity direction) compares False: out of domain
        return {"distance": d, "gravity_angle_rad": ang, "dynamics_distance": dyn, "in_domain": ok}

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
            return {
                "distance": np.array([d]),
                "gravity_angle_rad": np.array([np.nan]),
                "dynamics_distance": np.array([np.nan]),
                "in_domain": np.array([ok]),
            }
        cos = float(np.maximum.reduce(g.reshape(1, 3) @ dirs_t, axis=None))  # ndarray.max without its wrapper
        if math.isnan(cos):
            return None
        ang = float(np.arccos(min(max(cos, -1.0), 1.0)))  # np.clip of a number
        return {
            "distance": np.array([d]),
            "gravity_angle_rad": np.array([ang]),
            "dynamics_distance": np.array([np.nan]),
            "in_domain": np.array([ok and ang <= self.gravity_threshold_rad]),
        }


def domain_rate_reason(dom, recorded_hz: float | None) -> str | None:
    """The ``out_of_domain_reason`` of every window of a recording made at ``recorded_hz``, for a model with record ``dom``.

    ``"rate: recorded at 12 Hz, below the 20 Hz the model was trained at"`` when ``recorded_hz`` is below
    :data:`RATE_TOLERANCE` times ``dom.min_rate_hz`` (the recording holds less of the signal than any
    training recording: its fast detail is gone and predict's resampling interpolates it), ``""`` when
    it is not, None when not checked (no record, a record without a rate, or no rate given).
    """
    if dom is None or getattr(dom, "min_rate_hz", None) is None or recorded_hz is None:
        return None
    low = float(dom.min_rate_hz)
    if float(recorded_hz) < RATE_TOLERANCE * low:
        return f"rate: recorded at {float(recorded_hz):.3g} Hz, below the {low:.3g} Hz the model was trained at"
    return ""


def _record_range(v) -> float | None:
    """The record's ``acc_range_ms2`` (None when absent); ValueError when it is not an accelerometer range."""
    if v is None:
        return None
    from gaitml.errors import InputError
    from gaitml.features import check_acc_range

    try:
        r = check_acc_range(v)
    except InputError as exc:
        raise ValueError(f"acc_range_ms2 {v!r} is not an accelerometer range") from exc
    if r is None:
        raise ValueError(f"acc_range_ms2 {v!r} is not an accelerometer range")
    return r


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
