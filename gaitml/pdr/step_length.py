"""Step length models of paper 003 sec. 4.1: linear (walk, side, backward) and Weinberg (run).

- Linear model, eq. (12): ``L = A + B f + C var(a)`` with ``f`` the step frequency
  (1 / step period, Hz) and ``var(a)`` the variance of the acceleration magnitude over
  the step ((m/s^2)^2).
- Weinberg model, eq. (13): ``L = K (a_max - a_min)^(1/4)`` with ``a_max``, ``a_min``
  the extremes of the acceleration magnitude over the step (m/s^2).

``A, B, C`` and ``K`` are "obtained by training" (paper 003): :meth:`StepLengthModel.fit`
does least squares per mode from steps with known lengths, and
:meth:`StepLengthModel.calibrate` rescales a model so that a walk of known distance
comes out right (per-subject calibration).

Defaults when uncalibrated (stated, not from the paper, which gives no values):
walk ``A = 0.25 m, B = 0.25 m s, C = 0`` (0.70 m at 1.8 steps/s, a typical adult step),
backward ``A = 0.15, B = 0.15, C = 0`` (0.42 m at 1.8 Hz), side steps ``A = 0.15,
B = 0.12, C = 0`` (0.37 m at 1.8 Hz), run ``K = 0.55 m (m/s^2)^(-1/4)`` (about 1.16 m, a jogging step, for
a 20 m/s^2 magnitude range). They are order-of-magnitude values for an adult; calibrate
for distances better than ~20 %.

The acceleration used is the preprocessed magnitude of paper 003 sec. 2.1
(|acc| - g, moving average of N = 3), which does not change variance or range except
for the smoothing.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml._base import BaseAlgorithm
from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.io import write_json
from gaitml.signal import magnitude, moving_average

__all__ = [
    "DEFAULT_LINEAR",
    "DEFAULT_WEINBERG_K",
    "StepLengthModel",
    "linear_step_length",
    "step_length_features",
    "weinberg_step_length",
]

#: paper 003 sec. 2.1: moving average over N = 3 samples of |acc| - g.
SMOOTHING_SAMPLES = 3
#: Uncalibrated linear coefficients (A m, B m s, C m / (m/s^2)^2): stated defaults, see module doc.
DEFAULT_LINEAR: dict[str, tuple[float, float, float]] = {
    "walk": (0.25, 0.25, 0.0),
    "backward": (0.15, 0.15, 0.0),
    "side_left": (0.15, 0.12, 0.0),
    "side_right": (0.15, 0.12, 0.0),
}
#: Uncalibrated Weinberg constant for running (m (m/s^2)^-1/4): stated default, see module doc.
DEFAULT_WEINBERG_K = 0.55
#: Modes that use the Weinberg model (paper 003 sec. 4.1).
WEINBERG_MODES = ("run",)
FEATURE_COLUMNS = ("freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2")
#: A calibration records, per mode, the band of its inputs between these percentiles of the fitted steps
#: (eq. 12: cadence and variance; eq. 13: the magnitude range) ...
FIT_RANGE_PERCENTILES = (2.5, 97.5)
#: ... and a step whose input lies beyond the band by more than this fraction of its width is outside the
#: fit (its length is extrapolated: said by ``gaitml pdr``). Stated, not from the paper.
FIT_RANGE_MARGIN = 0.25


def linear_step_length(freq_hz, var_ms2sq, a: float, b: float, c: float) -> np.ndarray:
    """Paper 003 eq. (12): ``L = A + B f + C var(a)`` (m)."""
    return a + b * np.asarray(freq_hz, dtype=float) + c * np.asarray(var_ms2sq, dtype=float)


def weinberg_step_length(a_max_ms2, a_min_ms2, k: float) -> np.ndarray:
    """Paper 003 eq. (13), Weinberg: ``L = K (a_max - a_min)^(1/4)`` (m)."""
    rng = np.asarray(a_max_ms2, dtype=float) - np.asarray(a_min_ms2, dtype=float)
    return k * np.maximum(rng, 0.0) ** 0.25


def step_length_features(acc: np.ndarray, steps: pd.DataFrame, sampling_rate_hz: float) -> pd.DataFrame:
    """Per-step inputs of the step length models.

    Parameters
    ----------
    acc : array, shape (n, 3), m/s^2 with gravity.
    steps : DataFrame with ``start``, ``end`` (samples, end exclusive) and ``period_s``.
    sampling_rate_hz : float

    Returns
    -------
    DataFrame with ``freq_hz`` (1 / period_s), ``var_ms2sq``, ``a_max_ms2``, ``a_min_ms2``
    of the preprocessed magnitude over ``[start, end)``, one row per step.
    """
    a = np.asarray(acc, dtype=float)
    for col in ("start", "end", "period_s"):
        if col not in steps:
            raise InputError(f"the step table has no `{col}` column; pass a table from a gaitml step detector.")
    start = steps["start"].to_numpy(dtype=np.int64)
    end = steps["end"].to_numpy(dtype=np.int64)
    if len(start) and ((end <= start).any() or start.min() < 0 or end.max() > len(a)):
        raise InputError(f"step windows must satisfy 0 <= start < end <= {len(a)}; check the step table matches the recording.")
    mag = moving_average(magnitude(a) - GRAVITY_MS2, SMOOTHING_SAMPLES, mode="centered")
    n = len(start)
    # segment sums via cumulative sums (vectorised variance per step)
    c1 = np.concatenate([[0.0], np.cumsum(mag)])
    c2 = np.concatenate([[0.0], np.cumsum(mag * mag)])
    cnt = (end - start).astype(float)
    mean = (c1[end] - c1[start]) / np.maximum(cnt, 1)
    var = np.maximum((c2[end] - c2[start]) / np.maximum(cnt, 1) - mean**2, 0.0)
    # a loop over steps (not samples): a few hundred short slices
    amax = np.array([mag[s:e].max() for s, e in zip(start, end, strict=True)]) if n else np.zeros(0)
    amin = np.array([mag[s:e].min() for s, e in zip(start, end, strict=True)]) if n else np.zeros(0)
    period = steps["period_s"].to_numpy(dtype=float)
    with np.errstate(divide="ignore"):
        freq = np.where(period > 0, 1.0 / np.where(period > 0, period, 1.0), np.nan)
    return pd.DataFrame({"freq_hz": freq, "var_ms2sq": var, "a_max_ms2": amax, "a_min_ms2": amin}, index=steps.index)


class StepLengthModel(BaseAlgorithm):
    """Per-mode step length: linear eq. (12) for walk/side/backward, Weinberg eq. (13) for run.

    Parameters
    ----------
    coefficients : dict, optional
        ``{mode: ("linear", (A, B, C))}`` or ``{mode: ("weinberg", (K,))}``; missing
        modes take the stated defaults (module docstring). Unknown modes (real data
        sets' other classes) use the walk coefficients.

    Attributes
    ----------
    coefficients_ : dict mode -> (kind, params) in use.
    fitted_modes_ : list of modes whose coefficients were fitted or calibrated.
    calibration_ : dict, optional; how a calibration from truth fitted them (steps per mode, residuals;
        :func:`gaitml.pdr.calibrate.fit_step_lengths`), saved with the model.

    References
    ----------
    Paper 003 sec. 4.1, eqs. (12)-(13).
    """

    _action_method = "fit"

    def __init__(self, coefficients: dict | None = None):
        self.coefficients = coefficients

    def _configured(self) -> dict:
        """The stated defaults overridden by ``coefficients`` (validated)."""
        coef = {m: ("linear", tuple(p)) for m, p in DEFAULT_LINEAR.items()}
        coef["run"] = ("weinberg", (DEFAULT_WEINBERG_K,))
        if self.coefficients is not None and not isinstance(self.coefficients, dict):
            raise InputError(f"`coefficients` must be a dict mode -> (kind, params) or None, got {type(self.coefficients).__name__}.")
        for m, value in (self.coefficients or {}).items():
            try:
                kind, params = value
            except (TypeError, ValueError):
                raise InputError(f"`coefficients` for mode {m!r} must be (kind, params), got {value!r}.") from None
            coef[m] = _validate_coef(m, kind, params)
        return coef

    def coefficients_in_use(self) -> dict:
        """The coefficients in use: fitted / calibrated ones, else the configured ones."""
        return self.coefficients_ if hasattr(self, "coefficients_") else self._configured()

    # ------------------------------------------------------------------ fit
    def fit(self, features: pd.DataFrame, step_length_m, modes, *, min_steps: int = 5) -> StepLengthModel:
        """Least-squares fit per mode from steps with known lengths.

        Starts from the configured coefficients (``coefficients`` over the stated
        defaults); modes with fewer than ``min_steps`` steps keep them. Sets
        ``coefficients_`` and ``fitted_modes_``.
        The linear model is fitted with ``numpy.linalg.lstsq`` on ``[1, f, var]``;
        when the design is rank deficient (e.g. constant cadence) the minimum-norm
        solution is used. Weinberg's K is the closed-form least-squares slope
        through the origin of L against ``(a_max - a_min)^(1/4)``.
        """
        coef = self._configured()
        feats = _check_features(features)
        L = np.asarray(step_length_m, dtype=float).reshape(-1)
        modes = np.asarray(modes).astype(str).reshape(-1)
        if not (len(L) == len(modes) == len(feats)):
            raise InputError(f"features, step_length_m and modes must have the same length, got {len(feats)}, {len(L)}, {len(modes)}.")
        ok = np.isfinite(L) & np.isfinite(feats.to_numpy()).all(axis=1)
        fitted: list[str] = []
        for m in map(str, np.unique(modes)):
            sel = ok & (modes == m)
            if sel.sum() < min_steps:
                continue
            f = feats[sel]
            if m in WEINBERG_MODES:
                r = (np.maximum(f["a_max_ms2"] - f["a_min_ms2"], 0.0) ** 0.25).to_numpy()
                k = float(r @ L[sel] / max(r @ r, 1e-12))
                coef[m] = ("weinberg", (k,))
            else:
                X = np.column_stack([np.ones(sel.sum()), f["freq_hz"], f["var_ms2sq"]])
                c, *_ = np.linalg.lstsq(X, L[sel], rcond=None)
                coef[m] = ("linear", tuple(float(v) for v in c))
            fitted.append(m)
        self.coefficients_ = coef
        self.fitted_modes_ = fitted
        return self

    def calibrate(self, features: pd.DataFrame, modes, distance_m: float) -> StepLengthModel:
        """Per-subject calibration from a walk of known distance.

        The step lengths of the given steps are predicted with the current
        coefficients and every coefficient of the modes present is multiplied by
        ``distance_m / sum(predicted)`` so that the walk's total comes out right
        (a scale calibration: the shape of L(f, var) is kept).
        """
        if not (np.isfinite(distance_m) and distance_m > 0):
            raise InputError(f"`distance_m` must be a positive number of metres, got {distance_m!r}.")
        pred = self.predict(features, modes)
        total = float(np.nansum(pred))
        if total <= 0:
            raise InputError("the calibration walk has no steps with a positive predicted length; check the step table.")
        s = distance_m / total
        coef = dict(self.coefficients_in_use())
        fitted = list(getattr(self, "fitted_modes_", []))
        for m in map(str, np.unique(np.asarray(modes).astype(str))):
            kind, params = self._coef(m)
            coef[m] = (kind, tuple(p * s for p in params))
            if m not in fitted:
                fitted.append(m)
        self.coefficients_ = coef
        self.fitted_modes_ = fitted
        self.scale_ = s
        return self

    # -------------------------------------------------------------- predict
    def _coef(self, mode: str) -> tuple[str, tuple[float, ...]]:
        coef = self.coefficients_in_use()
        return coef.get(mode, coef["walk"])

    def predict(self, features: pd.DataFrame, modes) -> np.ndarray:
        """Step length (m) per step, by its mode; shape (n,). Negative values clip to 0."""
        feats = _check_features(features)
        modes = np.asarray(modes).astype(str).reshape(-1)
        if len(modes) != len(feats):
            raise InputError(f"`modes` must have one entry per step ({len(feats)}), got {len(modes)}.")
        out = np.full(len(feats), np.nan)
        for m in np.unique(modes):
            sel = modes == m
            kind, p = self._coef(m)
            f = feats[sel]
            if kind == "weinberg":
                out[sel] = weinberg_step_length(f["a_max_ms2"], f["a_min_ms2"], p[0])
            else:
                out[sel] = linear_step_length(f["freq_hz"], f["var_ms2sq"], *p)
        return np.clip(out, 0.0, None)

    def outside_fit(self, features: pd.DataFrame, modes) -> np.ndarray | None:
        """Which steps lie outside the inputs the model was calibrated on (shape (n,)); None without a record.

        A calibration from truth (:func:`gaitml.pdr.calibrate.fit_step_lengths`) keeps, per mode, the band of
        its inputs (:data:`FIT_RANGE_PERCENTILES`: cadence and variance for eq. 12, the magnitude range for
        eq. 13); a step is outside when an input lies beyond the band of the mode whose coefficients it takes
        (its own, or the walk line for a mode without coefficients, as :meth:`predict`) by more than
        :data:`FIT_RANGE_MARGIN` of its width (e.g. running steps given the walk line, forward-only), or when
        that mode has no band: the calibration did not fit it and its length is the stated default (e.g. run
        steps from a model's modes after a calibration on walks only).
        """
        record = getattr(self, "calibration_", None) or {}
        bands = {m: d.get("fitted_range") for m, d in (record.get("modes") or {}).items() if isinstance(d, dict) and d.get("fitted_range")}
        if not bands:
            return None
        feats = _check_features(features)
        modes = np.asarray(modes).astype(str).reshape(-1)
        if len(modes) != len(feats):
            raise InputError(f"`modes` must have one entry per step ({len(feats)}), got {len(modes)}.")
        coef = self.coefficients_in_use()
        used = np.array([m if m in coef else "walk" for m in modes], dtype=object)  # the coefficients each step takes
        values = {
            "freq_hz": feats["freq_hz"].to_numpy(float),
            "var_ms2sq": feats["var_ms2sq"].to_numpy(float),
            "range_ms2": (feats["a_max_ms2"] - feats["a_min_ms2"]).to_numpy(float),
        }
        out = np.zeros(len(feats), dtype=bool)
        for m in map(str, np.unique(used)):
            sel = used == m
            band = bands.get(m)
            if band is None:  # a mode the calibration did not fit: the stated default length
                out[sel] = True
                continue
            for name, (lo, hi) in band.items():
                pad = FIT_RANGE_MARGIN * (hi - lo)
                x = values[name][sel]
                out[sel] |= (x < lo - pad) | (x > hi + pad)
        return out

    # ------------------------------------------------------------ persistence
    def to_dict(self) -> dict:
        return {
            "format": "gaitml-step-length-v1",
            "coefficients": {m: {"kind": k, "params": list(p)} for m, (k, p) in self.coefficients_in_use().items()},
            "fitted_modes": list(getattr(self, "fitted_modes_", [])),
            **({"calibration": self.calibration_} if getattr(self, "calibration_", None) else {}),
        }

    @classmethod
    def from_dict(cls, d: dict) -> StepLengthModel:
        if not isinstance(d, dict) or d.get("format") != "gaitml-step-length-v1":
            raise InputError(
                "not a gaitml step length model (expected format 'gaitml-step-length-v1'); save one with StepLengthModel.save."
            )
        model = cls({m: (c["kind"], tuple(c["params"])) for m, c in d["coefficients"].items()})
        model.coefficients_ = model._configured()
        model.fitted_modes_ = list(d.get("fitted_modes", []))
        if isinstance(d.get("calibration"), dict):
            model.calibration_ = d["calibration"]
        return model

    def save(self, path) -> Path:
        """Write the coefficients as JSON (atomically)."""
        return write_json(path, self.to_dict())

    @classmethod
    def load(cls, path) -> StepLengthModel:
        p = Path(path)
        if not p.is_file():
            raise InputError(f"step length model file not found: {p}; pass a JSON file written by StepLengthModel.save.")
        try:
            d = json.loads(p.read_text())
        except json.JSONDecodeError as exc:
            raise InputError(f"step length model {p} is not valid JSON ({exc.msg}); re-save it.") from None
        return cls.from_dict(d)


def _validate_coef(mode, kind, params):
    params = tuple(float(x) for x in params)
    if kind == "linear" and len(params) == 3:
        return ("linear", params)
    if kind == "weinberg" and len(params) == 1:
        return ("weinberg", params)
    raise InputError(f"coefficients for mode {mode!r} must be ('linear', (A, B, C)) or ('weinberg', (K,)), got ({kind!r}, {params}).")


def _check_features(features) -> pd.DataFrame:
    if not isinstance(features, pd.DataFrame) or any(c not in features for c in FEATURE_COLUMNS):
        raise InputError(f"step length features must be a DataFrame with columns {list(FEATURE_COLUMNS)}; use step_length_features().")
    return features[list(FEATURE_COLUMNS)]
