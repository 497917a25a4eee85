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

The correction of step k uses only steps up to k (causal), so it can run online.
The defaults of the buffer tests (keywords of :func:`hde_correct` and
:class:`HeuristicDriftElimination`: buffer length, spread, trend between the buffer's
halves, consecutive passes) are ours, chosen on simulated routes to separate straight
legs from the 32 m radius bends of the 400 m arc route (``experiments/reports/pdr-step-modes.md``, "HDE defaults").

References
----------
Paper 003 sec. 4.2; Borenstein, Ojeda, Kwanmuang, "Heuristic reduction of gyro drift in
IMU-based personnel tracking systems", J. Navigation 62 (2009) (the HDE integrator).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from gaitml._base import NON_NEGATIVE, NON_NEGATIVE_INTEGER, POSITIVE, POSITIVE_INTEGER
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, wrap_angle
from gaitml.pdr.heading import BaseHeadingSource

__all__ = ["HeuristicDriftElimination", "estimate_drift_rate", "hde_correct", "hde_heading"]

#: paper 003 sec. 4.2: 12 dominant directions (30 deg sectors).
N_DIRECTIONS = 12
#: paper 003 sec. 4.2: feedback coefficient 0.01 (read per sample at 50 Hz, see module doc).
FEEDBACK_COEFFICIENT = 0.01
#: paper 003 works at 50 Hz (sec. 2.2: 15 samples = 0.3 s); the rate the coefficient refers to.
PAPER_RATE_HZ = 50.0
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
    max_rate_rads: float = 0.03,
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
    **hde_params,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Remove a fitted constant drift rate (``drift_rate='fit'``, module Notes step 5), then :func:`hde_correct`.

    Returns
    -------
    heading_rad, correction_rad, straight : as :func:`hde_correct`
    drift_rate_rads : the constant rate removed first (0 with ``drift_rate='none'``)
    """
    psi = np.asarray(heading_rad, dtype=float).reshape(-1)
    if drift_rate not in ("fit", "none"):
        raise InputError(f"`drift_rate` must be 'fit' or 'none', got {drift_rate!r}.")
    rate = 0.0
    if drift_rate == "fit" and len(psi) > 1:
        t = np.cumsum(np.full(len(psi), 0.5) if step_duration_s is None else step_duration_s) if step_t_s is None else step_t_s
        t = np.asarray(t, dtype=float)
        rate = estimate_drift_rate(psi, t, n_directions=n_directions, reference_rad=reference_rad)
        psi = psi - rate * (t - t[0])
    h, corr, straight = hde_correct(psi, step_duration_s, n_directions=n_directions, reference_rad=reference_rad, **hde_params)
    return h, corr, straight, rate


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
    attitude : AttitudeEstimator, optional
        Source of the gyro heading (default ``AttitudeEstimator()``).

    Attributes
    ----------
    heading_rad_ : corrected step headings.
    gyro_heading_rad_ : the raw (gyro) step headings corrected.
    correction_rad_ : correction applied per step.
    straight_ : bool per step, buffer judged straight.
    drift_rate_rads_ : fitted constant drift rate removed first (0 with ``drift_rate='none'``).
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
        self.attitude = attitude

    def hde_params(self) -> dict:
        """The keyword arguments of :func:`hde_heading`: every parameter but ``attitude``."""
        params = self.get_params(deep=False)
        del params["attitude"]
        return params

    def _heading(self, recording, steps, gyro_h, t_step, dur):
        h, self.correction_rad_, self.straight_, self.drift_rate_rads_ = hde_heading(gyro_h, dur, t_step, **self.hde_params())
        return h
