"""Acceleration-magnitude zero-velocity intervals with pseudo-zero rejection (paper 004).

Chen & Yang, "Step Counting Algorithm Based on Zero Velocity Update", Geomatics
and Information Science of Wuhan University 42(6), 2017 (``papers/004``), sec. 2.2.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from gaitml._base import NON_NEGATIVE, Interval, Options
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import magnitude
from gaitml.zupt._base import BaseZuptDetector, labelled_samples
from gaitml.zupt._intervals import INTERVAL_RULES, check_interval_rules, remove_short_runs, stride_scaled_stances
from gaitml.zupt.pseudo_std import _LazyPeriod

__all__ = ["MagnitudeZuptDetector", "magnitude_zupts", "DEFAULT_T_MIN_MS2", "DEFAULT_T_MAX_MS2", "MIN_RUN_FRACTION_OF_FS"]

#: Lower bound t_min of |a| (m/s^2, gravity included). Paper 004 prints no values for
#: T = [t_min, t_max]; we take the band 9-11 m/s^2 around g of the classic stance
#: condition C1 of Jimenez et al. (2009, the paper's ref. [4]).
DEFAULT_T_MIN_MS2 = 9.0
#: Upper bound t_max of |a| (m/s^2), see DEFAULT_T_MIN_MS2.
DEFAULT_T_MAX_MS2 = 11.0
#: paper 004 sec. 2.2 step (4): runs shorter than 10 % of the sampling frequency are pseudo-zero-velocity
MIN_RUN_FRACTION_OF_FS = 0.10


def magnitude_zupts(
    acc_mag_ms2: np.ndarray,
    sampling_rate_hz: float,
    *,
    t_min_ms2: float = DEFAULT_T_MIN_MS2,
    t_max_ms2: float = DEFAULT_T_MAX_MS2,
    min_run_fraction: float = MIN_RUN_FRACTION_OF_FS,
) -> np.ndarray:
    """``C(k) = t_min < |a(k)| < t_max`` (paper 004 eq. 3) with short runs removed.

    Runs of ``C = 1`` shorter than ``min_run_fraction * sampling_rate_hz`` samples
    (paper: 10 % of the sampling frequency, i.e. 5 samples at 50 Hz, 21 at
    204.8 Hz: a run of ``n`` samples is kept when ``n >= 0.1 fs``) are rejected as
    pseudo-zero-velocity points of the swing phase (step 4).

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    a = np.asarray(acc_mag_ms2, dtype=float)
    if a.ndim != 1:
        raise InputError(f"`acc_mag_ms2` must be 1-D, got shape {a.shape}.")
    if not t_min_ms2 < t_max_ms2:
        raise InputError(f"`t_min_ms2` must be < `t_max_ms2`, got {t_min_ms2} and {t_max_ms2}.")
    if min_run_fraction < 0:
        raise InputError(f"`min_run_fraction` must be >= 0, got {min_run_fraction}.")
    c = (a > t_min_ms2) & (a < t_max_ms2)
    return remove_short_runs(c, int(np.ceil(min_run_fraction * sampling_rate_hz - 1e-9)))


class MagnitudeZuptDetector(BaseZuptDetector):
    """Zero velocity where |a| stays inside ``(t_min, t_max)`` long enough (paper 004).

    Parameters
    ----------
    t_min_ms2, t_max_ms2 : float
        The band of eq. (3) on the magnitude of the specific force with gravity
        (default 9-11 m/s^2; the paper prints no values).
    min_run_fraction : float
        Runs shorter than this fraction of the sampling frequency (in samples)
        are rejected (paper: 0.10), under ``interval_rules='fixed'``.
    interval_rules : {'stride', 'fixed', 'none'}
        'fixed': paper 004's rule, runs shorter than ``min_run_fraction * fs`` samples
        are dropped. 'stride' (default): such a run is kept when it is the strongest run
        (the most summed margin inside the band) within half the local stride period of
        |a| (:func:`gaitml.zupt.stride_scaled_stances`; one stance per stride), dropped
        otherwise or where |a| shows no periodic gait. 'none': every run is kept.
    eps : float
        Fraction of labelled zero-velocity samples ``fit`` may leave outside the band
        (``eps/2`` on each side).

    Notes
    -----
    Paper 004 sec. 2.1 first rotates the acceleration to the east-north-up frame
    and then takes the magnitude of the three axes. A rotation does not change a
    vector's length, so the magnitude of the body-frame specific force is used
    directly (DESIGN sec. 4: "or use the frame-invariant magnitude"): during
    foot-flat it is g, hence the band around g instead of around 0.
    Works without a gyroscope.

    The paper's 0.1 s rejection was written for walking; a running foot lies flat
    for a few tens of ms (0.2-0.3 s of ground contact at 2.5-4 m/s; Novacheck,
    Gait & Posture 7, 1998), so the default keeps a short run when it is the one
    stance of its stride (see ``interval_rules``).

    References
    ----------
    Paper 004 (Chen & Yang, 2017), sec. 2.1-2.2.
    """

    name = "magnitude"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "eps": [Interval(0, 1, closed="neither")],
        "min_run_fraction": [NON_NEGATIVE],
        "interval_rules": [Options(INTERVAL_RULES)],
    }

    def __init__(
        self,
        *,
        t_min_ms2: float = DEFAULT_T_MIN_MS2,
        t_max_ms2: float = DEFAULT_T_MAX_MS2,
        min_run_fraction: float = MIN_RUN_FRACTION_OF_FS,
        eps: float = 0.002,
        interval_rules: str = "stride",
    ):
        self.t_min_ms2 = t_min_ms2
        self.t_max_ms2 = t_max_ms2
        self.min_run_fraction = min_run_fraction
        self.eps = eps
        self.interval_rules = interval_rules

    def _bounds(self) -> tuple[float, float]:
        if hasattr(self, "fitted_bounds_ms2_"):
            return self.fitted_bounds_ms2_
        return float(self.t_min_ms2), float(self.t_max_ms2)

    def _mask(self, recording: Recording):
        a = magnitude(recording.acc)
        lo, hi = self._bounds()
        self.t_min_ms2_, self.t_max_ms2_ = lo, hi
        rules = check_interval_rules(self.interval_rules)
        fs = recording.sampling_rate_hz
        if rules == "fixed":
            return magnitude_zupts(a, fs, t_min_ms2=lo, t_max_ms2=hi, min_run_fraction=self.min_run_fraction), a
        raw = magnitude_zupts(a, fs, t_min_ms2=lo, t_max_ms2=hi, min_run_fraction=0.0)
        if rules == "none":
            return raw, a
        shortest = int(np.ceil(self.min_run_fraction * fs - 1e-9))
        period = _LazyPeriod(a, fs)
        margin = np.minimum(a - lo, hi - a)
        mask = stride_scaled_stances(raw, period, fs, merge_gap_samples=0, min_interval_samples=shortest, evidence=margin)
        self.stride_s_ = period.value
        return mask, a

    def fit(self, recordings, reference=None) -> MagnitudeZuptDetector:
        """Set ``(t_min, t_max)`` to the ``eps/2`` and ``1 - eps/2`` quantiles of |a| on labelled samples."""
        self._validate_params()
        pairs = labelled_samples(recordings, reference)
        vals = np.concatenate([magnitude(r.acc)[m] for r, m in pairs])
        lo, hi = np.quantile(vals, [self.eps / 2, 1 - self.eps / 2])
        self.fitted_bounds_ms2_ = (float(lo), float(hi))
        return self
