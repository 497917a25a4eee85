"""Heuristic drift elimination (HDE) with a step buffer (paper 003 sec. 4.2).

Paper 003 corrects the gyro heading "based on the assumption that the pedestrian mainly
walks along dominant directions", citing a buffer-based improvement of HDE (its ref. [12],
Wang, Meng, Deng 2020, not in the shared papers), with 12 dominant directions 30 deg apart
and a feedback coefficient of 0.01. The paper gives no more detail; this module is our
reading, stated here so it can be judged and changed:

1. Corrected heading of step k: ``theta_k = psi_k + delta_k`` where ``psi_k`` is the raw
   (gyro) step heading and ``delta_k`` the accumulated correction (the HDE integrator of
   Borenstein et al. 2009).
2. Buffer: the last ``buffer_steps`` corrected step headings. The pedestrian is taken to
   walk straight when the buffer's heading spread (max absolute deviation from its
   circular mean) is below ``straight_spread_rad`` and its trend (difference of the
   circular means of its second and first halves) is below ``straight_trend_rad``. The
   trend test keeps HDE off on long gentle curves (an arc route), where the spread test
   alone would pass; the spread test keeps it off during turns. The tests must pass
   ``persist_steps`` (3) consecutive steps before the feedback acts: isolated noisy
   passes on a long bend would otherwise leave a wrong correction for the rest of it.
3. While straight, the error is ``E = D - mean(buffer)`` with ``D`` the nearest of the
   ``n_directions`` dominant directions (multiples of 2 pi / n from ``reference_rad``), and
   the correction is fed back proportionally: ``delta += g_k E``.
   Error gate (our addition, not in paper 003): the feedback acts only when
   ``|E| < max_error_rad`` (default 5 deg). A buffer that passes the straightness tests
   but whose mean heading is farther than that from every dominant direction is not a
   leg along a dominant direction: on the arc route it is the start or end of a bend, or
   a gentle stretch of it, where the literal rule (any ``|E|`` up to half a sector, 15 deg)
   pulls the heading towards a wrong direction. Residual drift after the drift-rate fit
   (step 5) is tracked continuously by the feedback, so on true legs ``E`` stays within a
   few degrees. The default was chosen on simulated route seeds and checked on others
   (``experiments/reports/pdr-step-modes.md``, "HDE defaults"); ``max_error_rad=np.pi``
   restores the literal rule.
4. Feedback coefficient: paper 003 gives 0.01 with no unit. Read per step it would take
   ~100 steps to remove half a 5 deg error, too slow to matter over a 262 m route; we read
   it as a per-sample coefficient at the paper's 50 Hz sampling rate (the heading update
   runs at the IMU rate), i.e. a correction rate ``-ln(1 - 0.01) * 50 = 0.50 1/s``, applied
   per step as ``g_k = 1 - exp(-rate * step_duration_s)`` (~0.22 for a 0.5 s step). Set
   ``feedback_per="step"`` for the literal per-step reading.

5. Drift rate (our addition): a constant gyro bias (the simulator draws up to 0.015 rad/s,
   0.86 deg/s, per axis: an uncalibrated phone gyro) makes a straight leg look curved,
   so the straightness tests fail, and the proportional feedback lags behind the drift.
   Before the buffered HDE, :func:`estimate_drift_rate` fits one constant heading drift
   rate to the whole recording (offline): the rate that best aligns the step headings
   with the dominant directions (maximum of the mean of ``cos(n (theta - reference))``
   over all steps). ``drift_rate='none'`` switches it off (with ``max_error_rad=np.pi``: the paper's method).
   An online integral correction of the rate (``b += k_i E dt``, as in Borenstein's HDE)
   locks onto the bends of a long arc, so it is not offered.

6. Structure guard (our addition, issue 27): HDE's premise is that the walker mainly walks
   along the dominant directions. A walk looping round a small room turns all the time, its
   step headings cover the circle, and the rate fit of step 5 then lines them up with the
   dominant directions by chance (``experiments/reports/tyrex-pdr.md``, "HDE in a room").
   :func:`direction_structure` tests the premise on the whole recording: the alignment score at
   the best rate, ``S = mean cos(n (theta - rate (t - t_0) - reference))``, against what headings
   without dominant-direction structure reach by chance. For N independent headings uniform on
   the circle ``P(|mean exp(i n theta)| > s) ~ exp(-N s^2)`` (the Rayleigh test applied to
   ``n theta``; Mardia and Jupp, *Directional Statistics*, Wiley 2000, sec. 6.3.1); ``S`` is at
   most that resultant length at every rate; the fit scans about
   ``K = 1 + n (2 max_rate) T / (2 pi)`` independent rates (over a recording of duration T the
   phase ``n r t`` turns by 2 pi when the rate moves by ``2 pi / (n T)``), so by the union bound
   ``P(max_r S > s) <= K exp(-N s^2)``, and the threshold is ``sqrt(ln(K / alpha) / N)`` with
   ``alpha`` = :data:`STRUCTURE_ALPHA`. At or below it HDE is not applied (neither the rate nor
   the feedback): the gyro step headings are returned unchanged. The Rayleigh tail is
   asymptotic and consecutive step headings are not independent (a few steps of one straight
   walk all line up), so with fewer than :data:`STRUCTURE_MIN_STEPS` steps the guard does not let
   HDE act either. ``structure_alpha=None`` (or 0) switches the guard off (HDE always applied:
   paper 003, and gaitml before the guard). The guard decides from the rate scan whether or not
   the rate is then removed (``drift_rate``), so the feedback-only variant is guarded the same way.

The correction of step k uses only steps up to k (causal), so it can run online (the rate
fit of step 5 and the guard of step 6 read the whole recording: offline).
The defaults of the buffer tests (keywords of :func:`hde_correct` and
:class:`HeuristicDriftElimination`: buffer length, spread, trend between the buffer's
halves, consecutive passes) are ours, chosen on simulated routes to separate straight
legs from the 32 m radius bends of the 400 m arc route (``experiments/reports/pdr-step-modes.md``, "HDE defaults").

References
----------
Paper 003 sec. 4.2; Borenstein, Ojeda, Kwanmuang, "Heuristic reduction of gyro drift in
IMU-based personnel tracking systems", J. Navigation 62 (2009) (the HDE integrator); K. V. Mardia,
P. E. Jupp, *Directional Statistics*, Wiley 2000, sec. 6.3.1 (the Rayleigh test, step 6).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from gaitml._base import NON_NEGATIVE, NON_NEGATIVE_INTEGER, POSITIVE, POSITIVE_INTEGER, Interval
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, wrap_angle
from gaitml.pdr.heading import BaseHeadingSource

__all__ = [
    "STRUCTURE_ALPHA",
    "STRUCTURE_MIN_STEPS",
    "HeuristicDriftElimination",
    "direction_structure",
    "estimate_drift_rate",
    "hde_correct",
    "hde_heading",
]

#: paper 003 sec. 4.2: 12 dominant directions (30 deg sectors).
N_DIRECTIONS = 12
#: paper 003 sec. 4.2: feedback coefficient 0.01 (read per sample at 50 Hz, see module doc).
FEEDBACK_COEFFICIENT = 0.01
#: paper 003 works at 50 Hz (sec. 2.2: 15 samples = 0.3 s); the rate the coefficient refers to.
PAPER_RATE_HZ = 50.0
#: half-width (rad/s) of the rate range :func:`estimate_drift_rate` scans (ours, module Notes step 5:
#: 1.7 deg/s, twice the simulator's largest per-axis gyro bias)
MAX_DRIFT_RATE_RADS = 0.03
#: the structure guard's false-alarm probability (module Notes step 6): the chance that step headings
#: without dominant-direction structure pass it. A conventional level (Mardia and Jupp 2000 sec. 6.3.1
#: tabulate the Rayleigh test at 0.01), set before measuring, not fitted (experiments/reports/tyrex-pdr.md)
STRUCTURE_ALPHA = 0.01
#: fewest steps on which the guard lets HDE act (module Notes step 6): the default ``buffer_steps`` (10) +
#: ``persist_steps`` (3), the fewest steps on which HDE's buffered feedback can change a heading at all (the
#: buffer is first full at step 10 and must pass 3 consecutive steps; the feedback then corrects the steps
#: after it). Below it only the rate fit would act, fitted on a few steps of one straight stretch, whose
#: headings line up whatever the walk and can pass the asymptotic threshold (experiments/reports/tyrex-pdr.md)
STRUCTURE_MIN_STEPS = 13
#: steps per block of the drift-rate score (bounds its memory: grid x block floats)
_SCORE_BLOCK = 4096


def _circmean(a: np.ndarray) -> float:
    return float(np.arctan2(np.sin(a).mean(), np.cos(a).mean()))


def estimate_drift_rate(
    heading_rad,
    t_s,
    *,
    n_directions: int = N_DIRECTIONS,
    reference_rad: float = 0.0,
    max_rate_rads: float = MAX_DRIFT_RATE_RADS,
    n_grid: int = 601,
) -> float:
    """Constant heading drift rate (rad/s) that best aligns step headings with the dominant directions.

    Maximises ``mean(cos(n (heading - rate t - reference)))`` over a grid of rates in
    ``[-max_rate_rads, max_rate_rads]`` and refines around the best one (vectorised:
    one (grid, steps) array). The corrected heading is ``heading - rate (t - t_0)``.
    """
    psi = np.unwrap(np.asarray(heading_rad, dtype=float).reshape(-1))
    t = np.asarray(t_s, dtype=float).reshape(-1)
    if psi.shape != t.shape:
        raise InputError(f"`heading_rad` and `t_s` must have the same length, got {psi.shape[0]} and {t.shape[0]}.")
    if len(psi) < 2:
        return 0.0
    t = t - t[0]
    rates = np.linspace(-max_rate_rads, max_rate_rads, n_grid)

    def score(r):
        # summed over blocks of steps: a (grid, block) array, not (grid, all steps), so a day of
        # steps (~10^5) costs tens of MB, not gigabytes
        total = np.zeros(len(r))
        for lo in range(0, len(psi), _SCORE_BLOCK):
            p, tt = psi[lo : lo + _SCORE_BLOCK], t[lo : lo + _SCORE_BLOCK]
            total += np.cos(n_directions * (p[None, :] - r[:, None] * tt[None, :] - reference_rad)).sum(axis=1)
        return total / len(psi)

    i = int(np.argmax(score(rates)))
    fine = np.linspace(rates[max(i - 1, 0)], rates[min(i + 1, n_grid - 1)], 201)
    return float(fine[int(np.argmax(score(fine)))])


def _guard_alpha(structure_alpha) -> float | None:
    """The guard's alpha, or None when the guard is off (``None`` or 0); refuses values outside [0, 1)."""
    if structure_alpha is None:
        return None
    try:
        a = float(structure_alpha)
    except (TypeError, ValueError):
        a = float("nan")
    if not 0 <= a < 1:
        raise InputError(f"`structure_alpha` must be in [0, 1) or None (0 or None: guard off), got {structure_alpha!r}.")
    return a or None


def _min_steps(min_steps, name: str) -> int:
    """A minimum step count: a whole number >= 0, else a one-line :class:`InputError`."""
    try:
        ok = float(min_steps).is_integer() and min_steps >= 0 and not isinstance(min_steps, bool)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise InputError(f"`{name}` must be a whole number >= 0, got {min_steps!r}.")
    return int(min_steps)


def direction_structure(
    heading_rad,
    t_s,
    rate_rads: float = 0.0,
    *,
    n_directions: int = N_DIRECTIONS,
    reference_rad: float = 0.0,
    alpha: float = STRUCTURE_ALPHA,
    max_rate_rads: float = MAX_DRIFT_RATE_RADS,
    min_steps: int = STRUCTURE_MIN_STEPS,
) -> dict:
    """Whether step headings line up with the dominant directions more than chance allows (module Notes step 6).

    ``rate_rads`` is the drift rate the score is taken at (the best one of the scan:
    :func:`estimate_drift_rate`); ``max_rate_rads`` the half-width of that scan.

    Returns
    -------
    dict with ``statistic`` (``mean cos(n (heading - rate (t - t_0) - reference))``), ``threshold``
    (``sqrt(ln(K / alpha) / N)``; None with fewer than 2 steps), ``n_steps`` (N), ``n_rates`` (K, the
    independent rates of the scan), ``alpha``, ``min_steps`` and ``structured`` (N >= ``min_steps`` and
    statistic > threshold).
    """
    psi = np.unwrap(np.asarray(heading_rad, dtype=float).reshape(-1))
    t = np.asarray(t_s, dtype=float).reshape(-1)
    if psi.shape != t.shape:
        raise InputError(f"`heading_rad` and `t_s` must have the same length, got {psi.shape[0]} and {t.shape[0]}.")
    if not (np.isfinite(psi).all() and np.isfinite(t).all()):
        raise InputError("`heading_rad` / `t_s` have NaN/inf values; interpolate them first.")
    if (np.diff(t) < 0).any():
        raise InputError("`t_s` must not decrease (step times in order); sort the steps by time first.")
    if _guard_alpha(alpha) is None:
        raise InputError(f"`alpha` must be in (0, 1), got {alpha!r}.")
    min_steps = _min_steps(min_steps, "min_steps")
    n = len(psi)
    rec = {"n_steps": n, "min_steps": min_steps, "alpha": float(alpha), "rate_rads": float(rate_rads)}
    if n < 2:
        return {**rec, "statistic": None, "threshold": None, "n_rates": None, "structured": False}
    k = 1.0 + n_directions * 2.0 * max_rate_rads * float(t[-1] - t[0]) / (2 * np.pi)
    stat = float(np.mean(np.cos(n_directions * (psi - rate_rads * (t - t[0]) - reference_rad))))
    thr = float(np.sqrt(np.log(k / alpha) / n))
    return {**rec, "statistic": stat, "threshold": thr, "n_rates": float(k), "structured": bool(n >= min_steps and stat > thr)}


def hde_correct(
    heading_rad,
    step_duration_s=None,
    *,
    n_directions: int = N_DIRECTIONS,
    reference_rad: float = 0.0,
    feedback: float = FEEDBACK_COEFFICIENT,
    feedback_per: str = "sample",
    buffer_steps: int = 10,
    straight_spread_rad: float = np.deg2rad(8.0),
    straight_trend_rad: float = np.deg2rad(2.0),
    lookahead_steps: int = 0,
    persist_steps: int = 3,
    max_error_rad: float = np.deg2rad(5.0),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Correct per-step headings with buffered heuristic drift elimination.

    Parameters
    ----------
    heading_rad : array (n,), raw step headings (rad, compass).
    step_duration_s : array (n,), optional; needed for ``feedback_per='sample'``
        (default 0.5 s per step when missing).
    n_directions, reference_rad : the dominant directions ``reference + j 2 pi / n``.
    feedback : feedback coefficient (paper 003: 0.01).
    feedback_per : {'sample', 'step'}, see module Notes (step 4).
    buffer_steps : steps in the buffer (>= 2).
    straight_spread_rad, straight_trend_rad : straight-walking tests (step 2).
    lookahead_steps : steps after k included in the straightness buffer (0: causal).
    persist_steps : the straightness tests must pass this many consecutive steps before
        the feedback acts (rejects isolated false detections on long bends).
    max_error_rad : the feedback acts only when the buffer's error ``|E|`` to the nearest
        dominant direction is below this (our gate, module Notes step 3; ``np.pi``: off).

    Returns
    -------
    corrected : (n,) corrected headings, wrapped.
    correction : (n,) the correction ``delta_k`` applied to each step.
    straight : (n,) bool, whether the buffer ending at step k was judged straight.
    """
    psi = np.asarray(heading_rad, dtype=float).reshape(-1)
    n = len(psi)
    if not np.isfinite(psi).all():
        raise InputError("`heading_rad` has NaN/inf values; interpolate the heading first.")
    if n_directions < 1:
        raise InputError(f"`n_directions` must be >= 1, got {n_directions}.")
    if not 0 <= feedback < 1:
        raise InputError(f"`feedback` must be in [0, 1), got {feedback}.")
    if buffer_steps < 2:
        raise InputError(f"`buffer_steps` must be >= 2, got {buffer_steps}.")
    dur = np.full(n, 0.5) if step_duration_s is None else np.asarray(step_duration_s, dtype=float).reshape(-1)
    if dur.shape != psi.shape:
        raise InputError(f"`step_duration_s` must have one value per step ({n}), got {dur.shape[0]}.")
    if not max_error_rad > 0:
        raise InputError(f"`max_error_rad` must be > 0, got {max_error_rad}.")
    if lookahead_steps < 0:
        raise InputError(f"`lookahead_steps` must be >= 0, got {lookahead_steps}.")
    if feedback_per == "sample":
        rate = -np.log1p(-feedback) * PAPER_RATE_HZ
        gains = 1.0 - np.exp(-rate * np.clip(dur, 0.0, None))
    elif feedback_per == "step":
        gains = np.full(n, feedback)
    else:
        raise InputError(f"`feedback_per` must be 'sample' or 'step', got {feedback_per!r}.")
    sector = 2 * np.pi / n_directions
    half = buffer_steps // 2
    corrected = np.empty(n)
    correction = np.empty(n)
    straight = np.zeros(n, dtype=bool)
    delta = 0.0  # heading offset correction
    la = int(lookahead_steps)
    run = 0  # consecutive steps judged straight
    for k in range(n):
        corrected[k] = psi[k] + delta
        correction[k] = delta
        if k + 1 < buffer_steps:
            continue
        # straightness from the raw headings (the corrected ones would look straighter
        # because of the correction itself: a positive feedback that locks curves); with a
        # look-ahead the buffer also holds the next steps (a delayed decision)
        hi = min(k + 1 + la, n)
        raw = psi[hi - buffer_steps : hi]
        spread = np.abs(wrap_angle(raw - _circmean(raw))).max()
        trend = abs(float(wrap_angle(_circmean(raw[half:]) - _circmean(raw[:half]))))
        run = run + 1 if (spread < straight_spread_rad and trend < straight_trend_rad) else 0
        if run >= persist_steps:
            straight[k] = True
            m = _circmean(corrected[k + 1 - buffer_steps : k + 1])
            dom = reference_rad + sector * np.round((m - reference_rad) / sector)
            err = float(wrap_angle(dom - m))
            if abs(err) < max_error_rad:
                delta += gains[k] * err
    return wrap_angle(corrected), correction, straight


def hde_heading(
    heading_rad,
    step_duration_s=None,
    step_t_s=None,
    *,
    drift_rate: str = "fit",
    n_directions: int = N_DIRECTIONS,
    reference_rad: float = 0.0,
    structure_alpha: float | None = STRUCTURE_ALPHA,
    structure_min_steps: int = STRUCTURE_MIN_STEPS,
    **hde_params,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, dict]:
    """The structure guard (module Notes step 6), then a fitted constant drift rate removed
    (``drift_rate='fit'``, step 5) and :func:`hde_correct`.

    ``structure_alpha``: the guard's false-alarm probability (None or 0: guard off, HDE always
    applied); ``structure_min_steps``: with the guard on, fewer steps than this leave the headings
    uncorrected. Step times default to the cumulated durations (0.5 s per step without them).

    Returns
    -------
    heading_rad, correction_rad, straight : as :func:`hde_correct` (with HDE held off: the input
        headings wrapped, zero corrections, no step straight)
    drift_rate_rads : the constant rate removed first (0 with ``drift_rate='none'`` or HDE held off)
    check : dict, :func:`direction_structure`'s record at the scan's best rate, with ``guard``
        ('on' / 'off'), ``hde_applied`` and ``reason`` (why HDE was held off: 'too few steps',
        'no dominant directions'; None when applied). With the guard off the record still says
        whether the headings are structured (at :data:`STRUCTURE_ALPHA`).
    """
    psi = np.asarray(heading_rad, dtype=float).reshape(-1)
    if drift_rate not in ("fit", "none"):
        raise InputError(f"`drift_rate` must be 'fit' or 'none', got {drift_rate!r}.")
    alpha = _guard_alpha(structure_alpha)
    structure_min_steps = _min_steps(structure_min_steps, "structure_min_steps")
    if not np.isfinite(psi).all():
        raise InputError("`heading_rad` has NaN/inf values; interpolate the heading first.")
    dur = np.full(len(psi), 0.5) if step_duration_s is None else np.asarray(step_duration_s, dtype=float).reshape(-1)
    if dur.shape != psi.shape:
        raise InputError(f"`step_duration_s` must have one value per step ({len(psi)}), got {dur.shape[0]}.")
    t = np.cumsum(dur) if step_t_s is None else np.asarray(step_t_s, dtype=float).reshape(-1)
    if t.shape != psi.shape:
        raise InputError(f"`step_t_s` must have one value per step ({len(psi)}), got {t.shape[0]}.")
    best = estimate_drift_rate(psi, t, n_directions=n_directions, reference_rad=reference_rad) if len(psi) > 1 else 0.0
    check = direction_structure(
        psi,
        t,
        best,
        n_directions=n_directions,
        reference_rad=reference_rad,
        alpha=alpha or STRUCTURE_ALPHA,
        min_steps=int(structure_min_steps),
    )
    reason = None
    if alpha is not None and not check["structured"]:
        reason = "too few steps" if len(psi) < structure_min_steps else "no dominant directions"
    check = {"guard": "off" if alpha is None else "on", **check, "hde_applied": reason is None, "reason": reason}
    if reason is not None:
        n = len(psi)
        return wrap_angle(psi), np.zeros(n), np.zeros(n, dtype=bool), 0.0, check
    rate = best if drift_rate == "fit" else 0.0
    if rate:
        psi = psi - rate * (t - t[0])
    h, corr, straight = hde_correct(psi, step_duration_s, n_directions=n_directions, reference_rad=reference_rad, **hde_params)
    return h, corr, straight, rate, check


class HeuristicDriftElimination(BaseHeadingSource):
    """Buffered HDE on the per-step gyro heading (paper 003 sec. 4.2); see :func:`hde_correct`.

    Parameters
    ----------
    n_directions : int, default 12
        Number of dominant directions, ``2 pi / n`` apart (paper 003: 12).
    reference_rad : float, default 0.0
        One dominant direction (rad, compass); the others follow every ``2 pi / n``.
    feedback : float, default 0.01
        Feedback coefficient (paper 003: 0.01).
    feedback_per : {'sample', 'step'}, default 'sample'
        Whether the feedback acts per sample or per step (module Notes, step 4).
    buffer_steps : int, default 10
        Length of the step buffer.
    straight_spread_rad, straight_trend_rad : float, default 8 / 2 deg
        Straight-walk tests on the buffer (module Notes, step 2).
    lookahead_steps : int, default 0
        Steps after the current one included in the buffer (offline only).
    persist_steps : int, default 3
        Consecutive straight steps before the feedback acts.
    max_error_rad : float, default 5 deg
        Larger errors against the nearest dominant direction are ignored.
    drift_rate : {'fit', 'none'}, default 'fit'
        Remove a fitted constant drift rate first (module Notes, step 5).
    structure_alpha : float or None, default :data:`STRUCTURE_ALPHA` (0.01)
        The structure guard's false-alarm probability (module Notes, step 6): HDE is applied only
        when the step headings line up with the dominant directions above chance. None or 0: guard
        off, HDE always applied (paper 003).
    structure_min_steps : int, default :data:`STRUCTURE_MIN_STEPS` (13)
        With the guard on, fewer steps than this leave the gyro headings uncorrected.
    attitude : AttitudeEstimator, optional
        Source of the gyro heading (default ``AttitudeEstimator()``).

    Attributes
    ----------
    heading_rad_ : corrected step headings.
    gyro_heading_rad_ : the raw (gyro) step headings corrected.
    correction_rad_ : correction applied per step.
    straight_ : bool per step, buffer judged straight.
    drift_rate_rads_ : fitted constant drift rate removed first (0 with ``drift_rate='none'`` or HDE held off).
    heading_check_ : dict, the guard's record (:func:`hde_heading`'s ``check``: statistic, threshold,
        n_steps, structured, hde_applied, reason).
    """

    name = "hde"
    steps_only = True
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "n_directions": [POSITIVE_INTEGER],
        "buffer_steps": [POSITIVE_INTEGER],
        "straight_spread_rad": [POSITIVE],
        "straight_trend_rad": [POSITIVE],
        "max_error_rad": [POSITIVE],
        "feedback": [NON_NEGATIVE],
        "lookahead_steps": [NON_NEGATIVE_INTEGER],
        "persist_steps": [NON_NEGATIVE_INTEGER],
        "structure_alpha": [Interval(0, 1, closed="left"), None],
        "structure_min_steps": [NON_NEGATIVE_INTEGER],
    }

    def __init__(
        self,
        *,
        n_directions: int = N_DIRECTIONS,
        reference_rad: float = 0.0,
        feedback: float = FEEDBACK_COEFFICIENT,
        feedback_per: str = "sample",
        buffer_steps: int = 10,
        straight_spread_rad: float = np.deg2rad(8.0),
        straight_trend_rad: float = np.deg2rad(2.0),
        lookahead_steps: int = 0,
        persist_steps: int = 3,
        max_error_rad: float = np.deg2rad(5.0),
        drift_rate: str = "fit",
        structure_alpha: float | None = STRUCTURE_ALPHA,
        structure_min_steps: int = STRUCTURE_MIN_STEPS,
        attitude: AttitudeEstimator | None = None,
    ):
        self.n_directions = n_directions
        self.reference_rad = reference_rad
        self.feedback = feedback
        self.feedback_per = feedback_per
        self.buffer_steps = buffer_steps
        self.straight_spread_rad = straight_spread_rad
        self.straight_trend_rad = straight_trend_rad
        self.lookahead_steps = lookahead_steps
        self.persist_steps = persist_steps
        self.max_error_rad = max_error_rad
        self.drift_rate = drift_rate
        self.structure_alpha = structure_alpha
        self.structure_min_steps = structure_min_steps
        self.attitude = attitude

    def hde_params(self) -> dict:
        """The keyword arguments of :func:`hde_heading`: every parameter but ``attitude``."""
        params = self.get_params(deep=False)
        del params["attitude"]
        return params

    def _heading(self, recording, steps, gyro_h, t_step, dur):
        h, self.correction_rad_, self.straight_, self.drift_rate_rads_, self.heading_check_ = hde_heading(
            gyro_h, dur, t_step, **self.hde_params()
        )
        return h
