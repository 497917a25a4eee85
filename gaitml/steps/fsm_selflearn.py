"""FSM step detection with threshold self-learning and step segmentation (paper 002, sec. 2).

Zhu et al., "Dynamic-Window PCA Algorithm for Step Direction Estimation",
J. Software, sec. 2.1-2.4: the magnitude ``M = |acc|`` (eq. 1) is low-passed at
4 Hz; an 8-state machine (S0 static, S1 possible motion, S2 / S3 entering /
leaving the peak, S4 / S6 entering / leaving the trough, S5 noise tolerance, S7
step end) with thresholds Thr, Thrpp, Thrnp, Thrneg (Table 1 initial values
10.3 / 10.4 / 9.3 / 9.4 m/s^2) counts a step at each S7. A learning phase updates
the peak and trough thresholds at every S7 (eqs. 2-3)::

    pp = 0.3 alpha max_i + 0.3 max_h + 0.4 thr
    np = 0.3 beta  min_i + 0.3 min_h + 0.4 thrneg

(``max_i`` the maximum in S2, ``min_i`` the minimum in S4 of the step just
completed, ``max_h`` / ``min_h`` those of the previous step), then the same
machine counts steps with the learned thresholds (sec. 2.4). The S2..S6
stretch of each step is the dynamic PCA window of sec. 3.1 (Fig. 10: S2~S6 is
the chosen cut).
"""

from __future__ import annotations

from bisect import bisect_left
from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import NON_NEGATIVE_INTEGER, POSITIVE
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import lowpass
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import acc_magnitude, as_recording, check_positive, segment_argmax
from gaitml.steps._table import make_step_table

__all__ = ["RATE_FLOOR_HZ", "SelfLearningFSMStepDetector", "selflearn_fsm_run", "learn_thresholds", "FSM_STATES"]

#: paper 002 Table 1 initial values (m/s^2)
THR_MS2 = 10.3
THR_PEAK_MS2 = 10.4
THR_TROUGH_MS2 = 9.3
THR_NEG_MS2 = 9.4
#: paper 002 sec. 2.1: 4 Hz low-pass
LOWPASS_HZ = 4.0
#: paper 002 sec. 2.3: alpha < 1, beta > 1 (values not printed). Ours: the fixed
#: point of eqs. (2)-(3) fitted to Table 3 (mean peak / learned threshold pairs
#: 11.29 / 10.82, 11.85 / 10.84, 16.16 / 13.14 give alpha ~ 0.86-0.98; mean trough
#: / learned pairs 8.55 / 9.29, 7.91 / 9.24, 5.25 / 7.52 give beta ~ 1.16-1.39).
ALPHA = 0.9
BETA = 1.3
#: paper 002 sec. 2.3: thresholds are stable after about 15 steps
LEARN_STEPS = 15
#: ours: the learning phase looks at most at the first 60 s (paper 002: about 10 s / 15 steps suffice)
LEARN_MAX_S = 60.0
#: ours: a step (S1..S5) longer than this is noise: back to S0 without counting
MAX_STEP_S = 2.0
#: ours: S6 ends the step when the next climb does not come within this time (the walker stopped)
END_TIMEOUT_S = 0.3

FSM_STATES = (
    "S0 static",
    "S1 possible motion",
    "S2 in peak",
    "S3 left peak",
    "S4 in trough",
    "S5 noise tolerance",
    "S6 left trough",
    "S7 step end",
)


def _transition(s: int, a: float, thr: float, pp: float, npk: float, neg: float) -> int:
    """One sample of the machine (level conditions only; timeouts are handled by the caller).

    S0 -> S1 when a > Thr. S1 -> S2 when a > Thrpp; S1 -> S0 when a < Thrneg
    (noise reset: no peak). S2 -> S3 when a < Thrpp. S3 -> S2 when a > Thrpp
    (noise: the peak resumes); S3 -> S4 when a < Thrnp. S4 -> S5 when a > Thrnp.
    S5 -> S4 when a < Thrnp (noise tolerance: the trough resumes); S5 -> S6 when
    a > Thrneg. S6 -> S7 (step) when a > Thr; S6 -> S4 when a < Thrnp (trough
    resumes). S7 is momentary (handled by the caller).
    """
    if s == 0:
        return 1 if a > thr else 0
    if s == 1:
        if a > pp:
            return 2
        return 0 if a < neg else 1
    if s == 2:
        return 3 if a < pp else 2
    if s == 3:
        if a > pp:
            return 2
        return 4 if a < npk else 3
    if s == 4:
        return 5 if a > npk else 4
    if s == 5:
        if a < npk:
            return 4
        return 6 if a > neg else 5
    # s == 6
    if a > thr:
        return 7
    return 4 if a < npk else 6


def selflearn_fsm_run(
    a: np.ndarray,
    thresholds: tuple[float, float, float, float],
    *,
    max_step_samples: int,
    end_timeout_samples: int,
    learn: bool = False,
    alpha: float = ALPHA,
    beta: float = BETA,
    learn_steps: int = LEARN_STEPS,
    jump: bool = True,
) -> tuple[np.ndarray, tuple[float, float, float, float], list]:
    """Run the machine over ``a``.

    Parameters
    ----------
    a : ndarray (n,)
        Low-passed |acc| (m/s^2).
    thresholds : (Thr, Thrpp, Thrnp, Thrneg)
    max_step_samples, end_timeout_samples : int
        Noise reset of a too-long step, and the end of a step whose next climb
        does not come.
    learn : bool
        Update Thrpp / Thrnp at every S7 (eqs. 2-3) and stop after
        ``learn_steps`` steps (the learning phase).
    jump : bool
        Visit only the state transitions (:func:`_count_fast`, exact: the
        machine reads only threshold comparisons and timeouts). Ignored when
        ``learn`` (the thresholds move). ``False`` is the plain per-sample loop.

    Returns
    -------
    events : int array (n_steps, 4)
        S1 entry (step start), S2 entry, S4 entry (first), S7 sample (end).
    thresholds : the final (Thr, Thrpp, Thrnp, Thrneg)
    history : list of (step, Thrpp, Thrnp) after each learning update
    """
    thr, pp, npk, neg = (float(v) for v in thresholds)
    x = np.asarray(a, dtype=float)
    n = len(x)
    if jump and not learn:
        return _count_fast(x, (thr, pp, npk, neg), max_step_samples, end_timeout_samples), (thr, pp, npk, neg), []
    xs = x.tolist()
    s = 0
    k = 0
    t1 = t2 = t4 = t6 = 0
    max_i = -np.inf
    min_i = np.inf
    max_h = min_h = None
    out = []
    hist = []
    while k < n:
        v = xs[k]
        if learn:
            if s == 2 and v > max_i:
                max_i = v
            elif s == 4 and v < min_i:
                min_i = v
        ns = _transition(s, v, thr, pp, npk, neg)
        if 1 <= s <= 5 and k - t1 >= max_step_samples:
            ns = 0  # noise reset: no step completes in time
        elif s == 6 and ns == 6 and k - t6 >= end_timeout_samples:
            ns = 7  # the walker stopped: the step ends without a new climb
        if ns != s:
            if ns == 7:
                out.append((t1, t2, t4, k))
                if learn:
                    if max_h is None:
                        max_h, min_h = max_i, min_i
                    pp = 0.3 * alpha * max_i + 0.3 * max_h + 0.4 * thr
                    npk = 0.3 * beta * min_i + 0.3 * min_h + 0.4 * neg
                    max_h, min_h = max_i, min_i
                    hist.append((len(out), pp, npk))
                    if len(out) >= learn_steps:
                        break
                ns = 1 if v > thr else 0
                t1 = k
                max_i, min_i = -np.inf, np.inf
            elif ns == 1 and s == 0:
                t1 = k
                max_i, min_i = -np.inf, np.inf
            elif ns == 2 and s == 1:
                t2 = k
                if learn and v > max_i:
                    max_i = v
            elif ns == 4 and s == 3:
                t4 = k
                if learn and v < min_i:
                    min_i = v
            elif ns == 6:
                t6 = k
            elif ns == 0:
                max_i, min_i = -np.inf, np.inf
            s = ns
            k += 1
            continue
        k += 1
    return np.asarray(out, dtype=np.int64).reshape(-1, 4), (thr, pp, npk, neg), hist


def _rising_edges(mask: np.ndarray) -> list:
    """Samples where ``mask`` becomes true (including sample 0 when it starts true)."""
    m = np.asarray(mask, dtype=bool)
    e = np.flatnonzero(m[1:] & ~m[:-1]) + 1
    if len(m) and m[0]:
        e = np.concatenate([[0], e])
    return e.tolist()


def _count_fast(x: np.ndarray, thresholds, max_step_samples: int, end_timeout_samples: int) -> np.ndarray:
    """The counting machine (fixed thresholds) visiting only state transitions.

    For each level condition the machine reads (``a > Thr``, ``a > Thrpp``,
    ``a < Thrpp``, ``a < Thrnp``, ``a > Thrnp``, ``a < Thrneg``, ``a > Thrneg``) the
    samples where it becomes true are precomputed with numpy; the next sample
    from k where it holds is k itself if it holds at k, else the next such edge
    (binary search). From a state entered at sample k the next transition is the
    earliest of its exit conditions (ties in the priority order of
    :func:`_transition`) or its timeout. Same result as the per-sample loop.
    """
    thr, pp, npk, neg = thresholds
    n = len(x)

    def edges(mask):
        e = _rising_edges(mask)
        e.append(n)  # sentinel: "never"
        return e

    e_gt_thr, e_gt_pp, e_lt_pp = edges(x > thr), edges(x > pp), edges(x < pp)
    e_lt_np, e_gt_np = edges(x < npk), edges(x > npk)
    e_lt_neg, e_gt_neg = edges(x < neg), edges(x > neg)
    bl = bisect_left
    out = []
    s, k = 0, 0  # state s holds from sample k on (k not yet processed)
    t1 = t2 = t4 = t6 = 0
    while k < n:
        v = x[k]
        if s == 0:
            k = k if v > thr else e_gt_thr[bl(e_gt_thr, k)]
            if k >= n:
                break
            s, t1 = 1, k
            k += 1
            continue
        if s == 6:
            j7 = k if v > thr else e_gt_thr[bl(e_gt_thr, k)]
            j4 = k if v < npk else e_lt_np[bl(e_lt_np, k)]
            dl = max(t6 + end_timeout_samples, k)  # the timeout acts only where no transition does
            j, ends_step = (j7, True) if j7 <= j4 else (j4, False)
            if dl < j:
                j, ends_step = dl, True
            if j >= n:
                break
            if ends_step:
                out.append((t1, t2, t4, j))
                if x[j] > thr:
                    s, t1 = 1, j
                else:
                    s = 0
            else:
                s = 4
            k = j + 1
            continue
        # states 1..5: the earliest exit, unless the step timeout comes first (it overrides a transition on its sample)
        if s == 1:
            ja = k if v > pp else e_gt_pp[bl(e_gt_pp, k)]
            jb = k if v < neg else e_lt_neg[bl(e_lt_neg, k)]
            j, ns = (ja, 2) if ja <= jb else (jb, 0)
        elif s == 2:
            j, ns = (k if v < pp else e_lt_pp[bl(e_lt_pp, k)]), 3
        elif s == 3:
            ja = k if v > pp else e_gt_pp[bl(e_gt_pp, k)]
            jb = k if v < npk else e_lt_np[bl(e_lt_np, k)]
            j, ns = (ja, 2) if ja <= jb else (jb, 4)
        elif s == 4:
            j, ns = (k if v > npk else e_gt_np[bl(e_gt_np, k)]), 5
        else:  # s == 5
            ja = k if v < npk else e_lt_np[bl(e_lt_np, k)]
            jb = k if v > neg else e_gt_neg[bl(e_gt_neg, k)]
            j, ns = (ja, 4) if ja <= jb else (jb, 6)
        dl = t1 + max_step_samples
        if dl <= j:
            j, ns = max(dl, k), 0
        if j >= n:
            break
        if ns == 2 and s == 1:
            t2 = j
        elif ns == 4 and s == 3:
            t4 = j
        elif ns == 6:
            t6 = j
        s = ns
        k = j + 1
    return np.asarray(out, dtype=np.int64).reshape(-1, 4)


def learn_thresholds(a, thresholds, *, max_step_samples, end_timeout_samples, alpha=ALPHA, beta=BETA, learn_steps=LEARN_STEPS):
    """The learning phase (paper 002 sec. 2.3): returns the learned (Thr, Thrpp, Thrnp, Thrneg) and the history."""
    _, th, hist = selflearn_fsm_run(
        a,
        thresholds,
        max_step_samples=max_step_samples,
        end_timeout_samples=end_timeout_samples,
        learn=True,
        alpha=alpha,
        beta=beta,
        learn_steps=learn_steps,
    )
    return th, hist


#: lowest recording rate (Hz) fsm-selflearn's count holds at: the floor rule of :mod:`gaitml.steps._rate` on
#: tyrex (the figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 30.0


class SelfLearningFSMStepDetector(BaseStepDetector):
    """FSM step detector with threshold self-learning (paper 002 sec. 2).

    Parameters
    ----------
    thr_ms2, thr_peak_ms2, thr_trough_ms2, thr_neg_ms2 : float
        Initial Thr, Thrpp, Thrnp, Thrneg (paper 002 Table 1: 10.3 / 10.4 / 9.3 / 9.4).
    alpha, beta : float, default 0.9 / 1.3
        Tolerance factors of eqs. (2)-(3) (alpha < 1, beta > 1; values ours, see
        the module constants).
    learn_steps : int, default 15
        Length of the learning phase in steps (sec. 2.3: about 15 steps / 10 s).
        0 disables learning (fixed thresholds).
    lowpass_hz : float, default 4.0
        Low-pass cut-off (sec. 2.1); zero-phase 4th-order Butterworth (offline).
    max_step_s, end_timeout_s : float, default 2.0 / 0.3
        Our noise / stop handling (Notes).

    Attributes
    ----------
    steps_ : DataFrame
        ``start`` = S1 entry, ``peak`` = maximum of the S2..S3 stretch, ``end`` =
        S7 sample (step completion, ``attrs['event'] = 't_end_s'``),
        ``period_s`` = end - start, plus ``s2``, ``s4`` (entries) and ``trough``.
    segments_ : DataFrame
        The S2..S6 step segments for DW-PCA (paper 002 sec. 3.1): ``start`` = S2
        entry, ``end`` = S7 sample (exclusive: the last S6 sample + 1),
        ``t_start_s``, ``t_end_s``, ``step`` (row of ``steps_``).
    thresholds_ : dict
        Learned ``thr_peak_ms2`` / ``thr_trough_ms2`` (and the fixed two).
    learning_ : DataFrame
        ``step``, ``thr_peak_ms2``, ``thr_trough_ms2`` after each learning update.

    Notes
    -----
    Fig. 3 (the transition diagram) is missing from the text; the transitions
    follow the state descriptions of sec. 2.2 and are listed in
    :func:`_transition`: S1 falls back to S0 below Thrneg without a peak, S3
    returns to S2 above Thrpp, S5 (noise tolerance) returns to S4 below Thrnp,
    S6 returns to S4 below Thrnp, and S6 -> S7 when the magnitude climbs above
    Thr again (the next step starts at that sample). Two safeguards are ours:
    a step not completed within ``max_step_s`` of its S1 entry is noise (back to
    S0), and S6 also ends the step after ``end_timeout_s`` without a new climb
    (the last step before standing still). The learning phase runs the machine
    on the start of the recording until ``learn_steps`` steps were learned (it
    looks at most at the first 60 s; fewer steps there leave the thresholds
    learned so far); then the whole recording is counted with the learned thresholds (offline
    reading of sec. 2.4: steps during the learning phase are counted too).

    References
    ----------
    Zhu et al., Dynamic-Window PCA Algorithm for Step Direction Estimation,
    J. Software (paper 002), sec. 2.1-2.4, 3.1, Tables 1 and 3.
    """

    name = "fsm-selflearn"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "lowpass_hz": [POSITIVE],
        "max_step_s": [POSITIVE],
        "end_timeout_s": [POSITIVE],
        "learn_steps": [NON_NEGATIVE_INTEGER],
    }

    def __init__(
        self,
        *,
        thr_ms2: float = THR_MS2,
        thr_peak_ms2: float = THR_PEAK_MS2,
        thr_trough_ms2: float = THR_TROUGH_MS2,
        thr_neg_ms2: float = THR_NEG_MS2,
        alpha: float = ALPHA,
        beta: float = BETA,
        learn_steps: int = LEARN_STEPS,
        lowpass_hz: float = LOWPASS_HZ,
        max_step_s: float = MAX_STEP_S,
        end_timeout_s: float = END_TIMEOUT_S,
    ):
        self.thr_ms2 = thr_ms2
        self.thr_peak_ms2 = thr_peak_ms2
        self.thr_trough_ms2 = thr_trough_ms2
        self.thr_neg_ms2 = thr_neg_ms2
        self.alpha = alpha
        self.beta = beta
        self.learn_steps = learn_steps
        self.lowpass_hz = lowpass_hz
        self.max_step_s = max_step_s
        self.end_timeout_s = end_timeout_s

    def detect(self, recording: Recording) -> SelfLearningFSMStepDetector:
        """Learn the thresholds on the start of ``recording``, then count its steps."""
        self._validate_params()
        rec = as_recording(recording, "fsm-selflearn step detection")
        fs = rec.sampling_rate_hz
        if int(self.learn_steps) != self.learn_steps or self.learn_steps < 0:
            raise InputError(f"`learn_steps` must be a non-negative integer, got {self.learn_steps!r}.")
        if not 0 < float(self.alpha) <= 1 or float(self.beta) < 1:
            raise InputError(f"need 0 < alpha <= 1 and beta >= 1 (paper 002 sec. 2.3), got alpha={self.alpha!r}, beta={self.beta!r}.")
        max_step = max(2, int(round(check_positive("max_step_s", self.max_step_s) * fs)))
        timeout = max(1, int(round(check_positive("end_timeout_s", self.end_timeout_s) * fs)))
        a = lowpass(acc_magnitude(rec), check_positive("lowpass_hz", self.lowpass_hz), fs)
        th0 = (float(self.thr_ms2), float(self.thr_peak_ms2), float(self.thr_trough_ms2), float(self.thr_neg_ms2))
        kw = dict(max_step_samples=max_step, end_timeout_samples=timeout)
        if self.learn_steps > 0:
            head = a[: int(LEARN_MAX_S * fs)]
            th, hist = learn_thresholds(head, th0, alpha=float(self.alpha), beta=float(self.beta), learn_steps=int(self.learn_steps), **kw)
        else:
            th, hist = th0, []
        ev, _, _ = selflearn_fsm_run(a, th, **kw)
        t1, t2, t4, t7 = (ev[:, i] for i in range(4))
        peak = segment_argmax(a, t2, t4)
        trough = segment_argmax(a, t4, t7, minimum=True)
        self.steps_: pd.DataFrame = make_step_table(t1, peak, t7, fs, event="t_end_s", s2=t2, s4=t4, trough=trough)
        self.segments_ = pd.DataFrame({"start": t2, "end": t7, "t_start_s": t2 / fs, "t_end_s": t7 / fs, "step": np.arange(len(t7))})
        self.thresholds_ = {"thr_ms2": th[0], "thr_peak_ms2": th[1], "thr_trough_ms2": th[2], "thr_neg_ms2": th[3]}
        self.learning_ = pd.DataFrame(hist, columns=["step", "thr_peak_ms2", "thr_trough_ms2"])
        return self
