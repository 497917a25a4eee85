"""Gyro pseudo-standard deviation with a Neyman-Pearson threshold (paper 001).

Dai et al., "Pedestrian navigation zero-velocity detection based on
pseudo-standard deviation and N-P criterion", J. Chinese Inertial Technology
26(6), 2018 (``papers/001``), sec. 1.2 (eqs. 1-8) and sec. 2 (eqs. 9-16).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from scipy.stats import norm

from gaitml._base import POSITIVE, Options, check_number
from gaitml.consts import DEG2RAD
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import magnitude
from gaitml.zupt._base import BaseZuptDetector, labelled_samples
from gaitml.zupt._intervals import (
    INTERVAL_RULES,
    apply_blockwise,
    centered_sums,
    check_interval_rules,
    half_window_samples,
    local_stride_period,
    merge_short_gaps,
    remove_short_runs,
    stride_scaled_stances,
)

__all__ = [
    "INTERVAL_RULES",
    "PAPER_EPS",
    "PAPER_MU1_RADS",
    "PAPER_S1_RADS",
    "PAPER_THRESHOLD_RADS",
    "PseudoStdZuptDetector",
    "fit_zero_velocity_normal",
    "check_interval_rules",
    "clean_stances",
    "np_threshold",
    "pseudo_std",
    "pseudo_std_tangent",
]

#: paper 001 sec. 3: mean of the pseudo-std on zero-velocity samples, 27.75 deg/s (100 Hz data)
PAPER_MU1_RADS = 27.75 * DEG2RAD
#: paper 001 sec. 3: its standard deviation S1, 13.07 deg/s
PAPER_S1_RADS = 13.07 * DEG2RAD
#: paper 001 sec. 3: missed-detection probability eps = 0.002 (u_0.998 = 2.88)
PAPER_EPS = 0.002
#: paper 001 eq. (16): the printed threshold 65.40 deg/s (2.88 x 13.07 + 27.75; the
#: text's unit "(deg)/h" in eq. 16 is a typo for deg/s, as the next sentence says).
PAPER_THRESHOLD_RADS = 65.40 * DEG2RAD
#: Half-window s in seconds. The paper does not print s; 0.05 s is s = 5 samples at the
#: paper's 100 Hz (an 11-sample window). s scales with the rate: s = round(0.05 fs).
DEFAULT_HALF_WINDOW_S = 0.05


def pseudo_std(gyr_mag: np.ndarray, half_window_samples: int) -> np.ndarray:
    """Pseudo-standard deviation of the gyro magnitude, exact form (paper 001 eqs. 6-7).

    For each sample i the window ``G(i) = g[i-s .. i+s]`` (2s+1 values) is
    extended with 2s+1 zeros (eq. 6) and the population standard deviation of
    the 4s+2 values is returned. With m and v the mean and variance of G(i):

        sigma'(i)^2 = v / 2 + m^2 / 4

    which is eq. (8) ``g(i)^2/4 + k^2 s(s+1)/6`` when g is linear over the window
    (then m = g(i) and v = k^2 s(s+1)/3, eq. 5). This exact form needs no
    derivative estimate. At the edges the window is truncated to the samples
    that exist and padded with as many zeros.

    Parameters
    ----------
    gyr_mag : ndarray, shape (n,)
        Gyro magnitude (rad/s), eq. (1).
    half_window_samples : int
        s >= 1.

    Returns
    -------
    ndarray, shape (n,), rad/s
    """
    g = np.asarray(gyr_mag, dtype=float)
    if g.ndim != 1:
        raise InputError(f"`gyr_mag` must be 1-D, got shape {g.shape}.")
    s = int(half_window_samples)
    if s < 1:
        raise InputError(f"`half_window_samples` must be >= 1, got {half_window_samples}.")
    sums, counts = centered_sums(np.stack([g, g * g], axis=1), s)
    mean = sums[:, 0] / counts
    var = np.maximum(sums[:, 1] / counts - mean * mean, 0.0)
    return np.sqrt(0.5 * var + 0.25 * mean * mean)


def pseudo_std_tangent(gyr_mag: np.ndarray, half_window_samples: int) -> np.ndarray:
    """Closed form of paper 001 eq. (8): ``sqrt(g(i)^2/4 + k^2 s(s+1)/6)``.

    ``k`` is the derivative of g at i per sample (central difference,
    ``np.gradient``). Equal to :func:`pseudo_std` when g is linear over each window.
    """
    g = np.asarray(gyr_mag, dtype=float)
    s = int(half_window_samples)
    if g.ndim != 1 or s < 1:
        raise InputError(f"`gyr_mag` must be 1-D and s >= 1, got shape {g.shape} and s={half_window_samples}.")
    k = np.gradient(g) if len(g) > 1 else np.zeros_like(g)
    return np.sqrt(0.25 * g * g + k * k * s * (s + 1) / 6.0)


def clean_stances(mask: np.ndarray, *, merge_gap_samples: int, min_interval_samples: int) -> np.ndarray:
    """Interval rules of the detector: merge short gaps, then drop short runs.

    1. A gap (run of non-zero-velocity samples between two zero-velocity runs) of
       at most ``merge_gap_samples`` is filled: it is a transient inside one stance
       (a heel-strike or impact spike), not a swing.
    2. A zero-velocity run shorter than ``min_interval_samples`` is dropped: it is a
       dip of the statistic in the swing (the gyro magnitude passes near zero where
       the foot's rotation reverses), not a stance.

    Merging first keeps the pieces of a stance that a spike split, even when each
    piece alone is shorter than the minimum.
    """
    return remove_short_runs(merge_short_gaps(mask, int(merge_gap_samples)), int(min_interval_samples))


def np_threshold(mu1: float, s1: float, eps: float) -> float:
    """Neyman-Pearson threshold ``mu1 + u_{1-eps} S1`` (paper 001 eqs. 11 and 15).

    ``u_{1-eps}`` is the standard normal quantile (``scipy.stats.norm.ppf``):
    u_0.998 = 2.878 gives 65.37 deg/s for the paper's mu1 = 27.75, S1 = 13.07 deg/s;
    the paper rounds u to 2.88 (a printed table) and prints 65.40 deg/s.
    """
    if not 0 < eps < 1:
        raise InputError(f"`eps` must be in (0, 1), got {eps!r}.")
    if s1 < 0:
        raise InputError(f"`s1` must be >= 0, got {s1!r}.")
    return float(mu1 + norm.ppf(1.0 - eps) * s1)


def fit_zero_velocity_normal(values: np.ndarray) -> tuple[float, float]:
    """Maximum-likelihood normal fit (mu1, S1) of pseudo-std values on zero-velocity samples.

    ML estimates of a normal: the sample mean and the population (1/N) standard
    deviation (paper 001 sec. 2, eq. 13 and sec. 3).
    """
    v = np.asarray(values, dtype=float).ravel()
    if v.size < 2:
        raise InputError(f"need at least 2 zero-velocity samples to fit mu1 and S1, got {v.size}.")
    return float(v.mean()), float(v.std())


class _LazyPeriod:
    """:func:`local_stride_period` of ``x`` at the positions asked (a block centred on each), recorded in ``value``.

    ``value`` is a per-sample array, NaN except at the positions asked (None when never asked). Centred
    blocks make the period at a position independent of where the recording starts, so a chunked run
    (:func:`gaitml.chunked_run.long_zupts`) decides as a whole-file run does.
    """

    def __init__(self, x: np.ndarray, sampling_rate_hz: float):
        self.x, self.fs, self.value = x, sampling_rate_hz, None

    def __call__(self, positions: np.ndarray) -> np.ndarray:
        out = local_stride_period(self.x, self.fs, at=positions)
        if self.value is None:
            self.value = np.full(len(self.x), np.nan)
        self.value[positions] = out
        return out


class PseudoStdZuptDetector(BaseZuptDetector):
    """Zero velocity where the gyro pseudo-std is below the N-P threshold (paper 001).

    Parameters
    ----------
    threshold_rads : float, optional
        Decision threshold on the pseudo-std (rad/s). Default: the paper's
        65.40 deg/s (eq. 16) = 1.1414 rad/s. ``fit`` replaces it.
    half_window_s : float
        Half-window s in seconds (default 0.05 s: s = 5 samples at 100 Hz,
        s = 10 at 204.8 Hz; ``s = round(half_window_s * fs)``). The paper does not
        print s. Keeping the window fixed in seconds keeps the statistic
        rate-independent: ``k`` is a per-sample derivative, so k^2 s(s+1) =
        (dg/dt)^2 (s/fs)^2 (1 + 1/s) is about the same at any rate.
    eps : float
        Allowed missed-detection probability used by ``fit`` (paper: 0.002).
    form : {'exact', 'tangent'}
        'exact' (default): std of the zero-padded window (eqs. 6-7);
        'tangent': the closed form eq. (8) with a central-difference derivative.
    interval_rules : {'stride', 'fixed', 'none'}
        What is done with the per-sample decision. 'stride' (default): gaps are filled
        and short runs judged against the local stride period of the gyro magnitude
        (:func:`gaitml.zupt.stride_scaled_stances`); 'fixed': gaps filled and short
        runs dropped by the lengths below alone (:func:`clean_stances`); 'none': the
        paper's per-sample rule, every run of samples is an interval.
    merge_gap_s : float, optional
        Gaps between two zero-velocity runs of at most this length (s) are filled.
        Default (None): one detector window, ``(2 s + 1) / fs`` (0.10 s at the
        default half-window); under 'stride' also at most a quarter of the local
        stride period. 0 disables it.
    min_interval_s : float, optional
        Zero-velocity runs of at least this length (s) are kept. Shorter runs are
        dropped under 'fixed'; under 'stride' a shorter run is kept when it is the
        strongest run (the most summed margin under the threshold) within half the
        local stride period. Default (None): one detector window. 0 disables it;
        ``merge_gap_s=0, min_interval_s=0`` is the per-sample rule, as 'none'.

    Attributes
    ----------
    per_sample_zupts_, zupts_, statistic_ : see :class:`BaseZuptDetector`.
    mu1_rads_, s1_rads_ : fitted normal of the zero-velocity pseudo-std (after ``fit``).
    threshold_rads_ : the threshold used by ``detect``.
    stride_s_ : local stride period (s) at the gaps and short runs that needed it (NaN elsewhere or
        without gait) with ``interval_rules='stride'``; None when none needed it.

    Notes
    -----
    Paper 001 sec. 1.2 defines the pseudo-std by eqs. (6)-(7) and derives the
    closed form (8) under a tangent-line approximation; both are offered. The
    decision rule (15) is ``sigma' < mu1 + u_{1-eps} S1``. The paper's mu1, S1
    were fitted at 100 Hz on heel-mounted MIMU data; the gyro magnitude does not
    depend on the rate, and with s fixed in seconds neither does the statistic.

    Interval rules (not in paper 001, which classifies samples only). On
    foot-mounted data the per-sample rule produces two kinds of wrong intervals
    (``experiments/reports/zupt-heldout.md``): short runs in the swing, where the
    gyro magnitude dips through a minimum because the foot's rotation reverses
    (mid-swing on stairs, terminal swing before heel strike; |a| is far from g
    there), and stances cut in two by a brief spike. The statistic itself fixes the
    scale of both: a spike of one sample lifts sigma' over one window of ``2 s + 1``
    samples, so a gap of up to one window is what a transient leaves; and a run
    shorter than one window contains no window of rest, so sigma' never saw the foot
    still. Both rules therefore use one detector window (0.10 s). Physiology leaves
    a wide margin on both sides: the shortest swing of human gait is ~0.3 s (a
    sprint) and a walking foot-flat lasts ~0.3-0.5 s. Paper 004 rejects zero-velocity
    runs shorter than 0.1 s ("pseudo zero velocity") with the same reasoning.
    A rule in seconds does not scale with the gait: a running stance holds a
    zero-velocity run of a few tens of ms (ground contact 0.2-0.3 s at 2.5-4 m/s;
    Novacheck, Gait & Posture 7, 1998; Weyand et al., J. Appl. Physiol. 89, 2000),
    shorter than one window. The default rule 'stride' uses instead the physics of
    gait that holds at any speed: each stride of a foot has exactly one stance. Short
    runs are kept when they are the strongest within half the local stride period
    (found by :func:`gaitml.zupt.local_stride_period` on the gyro magnitude), so a
    running stance survives and a swing dip beside a stronger stance does not; the
    gap rule is capped at a quarter of a stride (the swing is longer). Without
    periodic gait the 'fixed' rule applies.

    References
    ----------
    Paper 001 (Dai et al., 2018), sec. 1.2, 2, 3.
    """

    name = "pseudo-std"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "half_window_s": [POSITIVE],
        "eps": [POSITIVE],
        "interval_rules": [Options(INTERVAL_RULES)],
    }

    def __init__(
        self,
        *,
        threshold_rads: float | None = None,
        half_window_s: float = DEFAULT_HALF_WINDOW_S,
        eps: float = PAPER_EPS,
        form: str = "exact",
        interval_rules: str = "stride",
        merge_gap_s: float | None = None,
        min_interval_s: float | None = None,
    ):
        self.threshold_rads = threshold_rads
        self.half_window_s = half_window_s
        self.eps = eps
        self.form = form
        self.interval_rules = interval_rules
        self.merge_gap_s = merge_gap_s
        self.min_interval_s = min_interval_s

    def _statistic(self, recording: Recording) -> np.ndarray:
        gyr = recording.require_gyr("the pseudo-std zero-velocity detector (paper 001)")
        s = half_window_samples(self.half_window_s, recording.sampling_rate_hz)
        g = magnitude(gyr)
        if self.form == "exact":
            return apply_blockwise(lambda x: pseudo_std(x, s), (g,), s)
        if self.form == "tangent":
            return apply_blockwise(lambda x: pseudo_std_tangent(x, s), (g,), s + 1)
        raise InputError(f"`form` must be 'exact' or 'tangent', got {self.form!r}.")

    def _threshold(self) -> float:
        if hasattr(self, "fitted_threshold_rads_"):
            return self.fitted_threshold_rads_
        thr = PAPER_THRESHOLD_RADS if self.threshold_rads is None else float(self.threshold_rads)
        if not np.isfinite(thr) or thr <= 0:
            raise InputError(f"`threshold_rads` must be a positive number (rad/s), got {self.threshold_rads!r}.")
        return thr

    def _window_samples(self, sampling_rate_hz: float) -> int:
        return 2 * half_window_samples(self.half_window_s, sampling_rate_hz) + 1

    def _rule_samples(self, value: float | None, name: str, sampling_rate_hz: float) -> int:
        """An interval-rule length in samples (None: one detector window)."""
        if value is None:
            return self._window_samples(sampling_rate_hz)
        return int(round(check_number(name, value, non_negative=True) * float(sampling_rate_hz)))

    def _mask(self, recording):
        fs = recording.sampling_rate_hz
        rules = check_interval_rules(self.interval_rules)
        gap = self._rule_samples(self.merge_gap_s, "merge_gap_s", fs) if rules != "none" else 0
        shortest = self._rule_samples(self.min_interval_s, "min_interval_s", fs) if rules != "none" else 0
        stat = self._statistic(recording)
        thr = self._threshold()
        self.threshold_rads_ = thr
        self.merge_gap_samples_ = gap
        self.min_interval_samples_ = shortest
        raw = stat < thr
        if rules == "stride":
            period = _LazyPeriod(magnitude(recording.gyr), fs)
            mask = stride_scaled_stances(raw, period, fs, merge_gap_samples=gap, min_interval_samples=shortest, evidence=thr - stat)
            self.stride_s_ = period.value
            return mask, stat
        return clean_stances(raw, merge_gap_samples=gap, min_interval_samples=shortest), stat

    def fit(self, recordings, reference=None) -> PseudoStdZuptDetector:
        """Fit mu1, S1 on labelled zero-velocity samples and set the N-P threshold.

        Parameters
        ----------
        recordings : Recording or sequence of Recording
        reference : sequence of bool arrays, optional
            One per recording, True on labelled zero-velocity samples. Default:
            :func:`gaitml.zupt.reference_zupt_mask` (samples within 50 ms of
            each motion-capture ``min_vel`` sample).

        Returns
        -------
        self, with ``mu1_rads_``, ``s1_rads_`` and ``fitted_threshold_rads_ = mu1 + u_{1-eps} S1``
            (used by later ``detect`` calls instead of ``threshold_rads``).
        """
        self._validate_params()
        pairs = labelled_samples(recordings, reference)
        vals = np.concatenate([self._statistic(r)[m] for r, m in pairs])
        self.mu1_rads_, self.s1_rads_ = fit_zero_velocity_normal(vals)
        self.fitted_threshold_rads_ = np_threshold(self.mu1_rads_, self.s1_rads_, self.eps)
        self.threshold_rads_ = self.fitted_threshold_rads_
        self.n_fit_samples_ = int(vals.size)
        return self
