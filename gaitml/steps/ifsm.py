"""Improved finite state machine (IFSM) step detection (paper 000, sec. 2).

Bi et al., "Improved Finite State Machine Step Detection Algorithm for
Smartphone", Geomatics and Information Science of Wuhan University 2021,
sec. 2.1-2.3 and Table 1. The magnitude ``A = |acc|`` (eq. 1) is smoothed with a
5-sample moving average; a step runs through the seven states
s0 start - s1 climb - s2 peak - s3 descend - s4 trough - s5 climb - s6 end, with
climb / descend counters (eq. 2: a climb when ``A_k - A_{k-1} > A_diff``, a
descent when ``< -A_diff``). The step period is ``t_e - t_0``.

Two readings of the printed text are implemented (see :class:`IFSMStepDetector`).
"""

from __future__ import annotations

from bisect import bisect_left
from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import NON_NEGATIVE, POSITIVE_INTEGER
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import moving_average
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import acc_magnitude, as_recording, map_indices, resample_signal
from gaitml.steps._table import make_step_table

__all__ = ["RATE_FLOOR_HZ", "LITERAL_RATE_FLOOR_HZ", "IFSMStepDetector", "IFSMLiteralStepDetector", "ifsm_steps", "IFSM_READINGS"]

#: paper 000 Table 1: A_Thr = 9.81 m/s^2 (enter s1)
MAGNITUDE_THRESHOLD_MS2 = 9.81
#: paper 000 Table 1: A_diff_Thr = 0.04 m/s^2 between adjacent samples
DIFF_THRESHOLD_MS2 = 0.04
#: paper 000 Table 1: T_Cl_Thr_1 = 4 climbs before the peak
FIRST_CLIMBS = 4
#: paper 000 Table 1: T_De_Thr = 7 descents before the trough
DESCENTS = 7
#: paper 000 Table 1: T_Cl_Thr_2 = 5 climbs after the trough
SECOND_CLIMBS = 5
#: paper 000 Table 1: T_Dis_Thr = 3 descents that break a climb (noise reset)
DISTURB_DESCENTS = 3
#: paper 000 Table 1: delta = 0.2 m/s^2 tolerance of the end state
END_TOLERANCE_MS2 = 0.2
#: paper 000 sec. 2.1: moving average of 5 samples
SMOOTHING_SAMPLES = 5
#: paper 000 sec. 3.1: data at 50 Hz; the counters are samples at this rate
DESIGN_RATE_HZ = 50.0

#: reading name -> (count the s0 -> s1 sample as a climb, thresholds inclusive (>=), end condition)
IFSM_READINGS = {
    "reproduce": (True, True, "recovered"),
    "literal": (False, False, "always"),
}


def _check_reading(count_entry, inclusive, end_condition):
    if end_condition not in ("recovered", "always"):
        raise InputError(f"`end_condition` must be 'recovered' or 'always', got {end_condition!r}.")


def ifsm_steps(
    A: np.ndarray,
    *,
    magnitude_threshold_ms2: float = MAGNITUDE_THRESHOLD_MS2,
    diff_threshold_ms2: float = DIFF_THRESHOLD_MS2,
    first_climbs: int = FIRST_CLIMBS,
    descents: int = DESCENTS,
    second_climbs: int = SECOND_CLIMBS,
    disturb_descents: int = DISTURB_DESCENTS,
    end_tolerance_ms2: float = END_TOLERANCE_MS2,
    count_entry: bool = True,
    inclusive: bool = True,
    end_condition: str = "recovered",
) -> np.ndarray:
    """Run the IFSM over a smoothed magnitude ``A`` (m/s^2, 50 Hz samples).

    States (paper 000 sec. 2.3, steps 1-8): s0 resets both counters and moves to
    s1 at the first sample with ``A_k > A_T`` (``t_0``); s1 counts climbs and
    descents, returns to s0 when the descents reach ``disturb_descents`` (noise
    reset), and moves to the peak s2 when the climbs pass ``first_climbs`` at a
    local maximum (``A_{k-1} < A_k > A_{k+1}``); s2 clears the descents (s3);
    s3 counts descents and moves to the trough s4 when they pass ``descents`` at
    a local minimum; s4 clears the climbs (s5); s5 counts climbs and moves to the
    end s6 when they pass ``second_climbs`` and the end condition holds; s6
    counts the step (``t_e``) and returns to s0.

    The machine is evaluated exactly as a per-sample loop over the states would
    (``tests/steps/reference_fsm.py`` keeps that loop as the test reference), but
    the Python loop runs over steps. The
    counters are cumulative sums, so "the first sample where a counter reaches
    c" is a binary search; the outcome of s1 (peak or noise reset) depends only
    on t_0 and is computed for every candidate t_0 at once, the trough for
    every local maximum and the end for every local minimum likewise; chains
    of noise resets are collapsed by pointer jumping (numpy), so the loop only
    visits detected steps.

    Parameters
    ----------
    A : ndarray (n,)
        Smoothed |acc| in m/s^2 at the design rate (50 Hz).
    count_entry, inclusive, end_condition
        The reading (see :class:`IFSMStepDetector`).

    Returns
    -------
    ndarray (n_steps, 4) of int: ``t0``, peak, trough, ``t_e`` samples.
    """
    _check_reading(count_entry, inclusive, end_condition)
    A = np.asarray(A, dtype=float)
    n = len(A)
    if n < 3:
        return np.zeros((0, 4), dtype=np.int64)
    off = 0 if inclusive else 1
    c1, cd, c2 = first_climbs + off, descents + off, second_climbs + off
    d = np.empty(n)
    d[0] = 0.0
    np.subtract(A[1:], A[:-1], out=d[1:])
    # eq. (2): climbs / descents counted as cumulative sums, so 'the first k where a counter reaches c' is a search
    CU = np.cumsum(d > diff_threshold_ms2)
    CD = np.cumsum(d < -diff_threshold_ms2)
    last = n - 2
    mid = A[1:-1]
    lmax = np.flatnonzero((mid > A[:-2]) & (mid > A[2:])) + 1
    lmin = np.flatnonzero((mid < A[:-2]) & (mid < A[2:])) + 1
    above = np.flatnonzero(A[1:-1] > magnitude_threshold_ms2) + 1
    if end_condition == "always":
        ends = np.arange(1, n - 1)
    else:
        ends = np.flatnonzero(A[1:-1] > magnitude_threshold_ms2 - end_tolerance_ms2) + 1
    big = n + 1  # "never"

    def next_in(sorted_idx, k):
        j = np.searchsorted(sorted_idx, k)
        return np.where(j < len(sorted_idx), sorted_idx[np.minimum(j, len(sorted_idx) - 1)] if len(sorted_idx) else big, big)

    # s1 outcome of every possible t0 (every sample above A_T), all at once
    first = above if count_entry else above + 1
    base = first - 1
    k_reset = np.searchsorted(CD, CD[base] + disturb_descents, side="left")  # >= first since the count starts at 0
    k_peak = next_in(lmax, np.searchsorted(CU, CU[base] + c1, side="left"))
    ok = (k_peak < k_reset) & (k_peak <= last)
    dead = ~ok & ((k_reset > last) | (k_reset >= big))
    m = len(above)
    # successor of a failed attempt: the next t0 after its reset sample; pointer jumping finds the first success
    succ = np.where(ok, np.arange(m), np.where(dead, m, np.searchsorted(above, k_reset + 1)))
    succ = np.append(succ, m)
    for _ in range(int(np.ceil(np.log2(m + 2))) + 1):
        nxt = succ[succ]
        if np.array_equal(nxt, succ):
            break
        succ = nxt
    # s3 -> s4 for every possible peak, s5 -> s6 for every possible trough
    trough_of = next_in(lmin, np.searchsorted(CD, CD[lmax] + cd, side="left"))
    end_of = next_in(ends, np.searchsorted(CU, CU[lmin] + c2, side="left"))
    above_l, succ_l, kpeak_l = above.tolist(), succ.tolist(), k_peak.tolist()
    lmax_l, lmin_l, trough_l, end_l = lmax.tolist(), lmin.tolist(), trough_of.tolist(), end_of.tolist()
    # one iteration per detected step: from sample `cur` the first t0 whose s1 ends in a peak (s0 -> s1 -> s2),
    # then that peak's trough (s3 -> s4) and that trough's end (s5 -> s6); s6 hands back to s0 at ke + 1
    out = []
    cur = 1
    while True:
        i = succ_l[bisect_left(above_l, cur)] if cur <= (above_l[-1] if m else -1) else m
        if i >= m:
            break
        t0, kp = above_l[i], kpeak_l[i]
        kt = trough_l[bisect_left(lmax_l, kp)]
        if kt > last:
            break
        ke = end_l[bisect_left(lmin_l, kt)]
        if ke > last:
            break
        out.append((t0, kp, kt, ke))
        cur = ke + 1
    return np.asarray(out, dtype=np.int64).reshape(-1, 4)


#: lowest recording rate (Hz) ifsm's count holds at: paper 000 records at 50 Hz (sec. 3.1) and the machine runs
#: on a 50 Hz resampling; the floor rule of :mod:`gaitml.steps._rate` on tyrex gives 10 Hz, the lowest rate
#: measured (the figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 10.0


class IFSMStepDetector(BaseStepDetector):
    """Improved finite state machine step detector (paper 000 sec. 2, Table 1).

    Parameters
    ----------
    reading : {'reproduce', 'literal'}, default 'reproduce'
        How to read the ambiguous printed text (Notes).
    magnitude_threshold_ms2 : float, default 9.81
        A_T (Table 1): enter s1; the end state is tested against it.
    diff_threshold_ms2 : float, default 0.04
        A_D^T (Table 1): adjacent-sample difference counted as a climb/descent.
    first_climbs, descents, second_climbs : int, default 4 / 7 / 5
        T_C^1, T_D^T, T_C^2 (Table 1), in samples at 50 Hz.
    disturb_descents : int, default 3
        T_C^D (Table 1): descents during the first climb that reset to s0.
    end_tolerance_ms2 : float, default 0.2
        delta (Table 1).
    smoothing_samples : int, default 5
        Moving average (sec. 2.1), centred, at 50 Hz.

    Attributes
    ----------
    steps_ : DataFrame
        DESIGN step table: ``start`` = t_0, ``peak`` = s2 sample, ``end`` = t_e (so
        ``t_end_s`` is the step completion time, ``attrs['event'] = 't_end_s'``),
        ``period_s`` = t_e - t_0 (sec. 2.3 step 8), ``trough`` = s4 sample.

    Notes
    -----
    The counters and thresholds are samples at 50 Hz (the paper's rate). A
    recording at another rate is linearly resampled to 50 Hz, the machine runs
    there, and the indices are mapped back to the recording's rate.

    **Reading 'reproduce'** (default; reproduces Table 2 on the paper's own data
    within one step: 283 / 319 for the true 284 / 319, and the period of the
    first 10 steps of file 1 within 0.02 s on average of the manually read
    durations of Table 3; the one step short on file 1 is its last peak, 0.4 s
    before the end of the recording, whose descent is cut off):

    - the end condition of step 6 is printed as "A_k > A_T - delta or A_k <
      A_T + delta", which is always true; we read it as "A_k > A_T - delta": the
      magnitude has climbed back to within delta of gravity (s6 "the magnitude
      returns to the level of s0"). The two-sided band |A_k - A_T| < delta
      is skipped over by the 50 Hz samples of a fast climb and misses about half
      of the steps;
    - the sample where s0 sees A_k > A_T is itself counted by eq. (2) (the
      climb is already under way when the threshold is crossed);
    - "greater than the threshold" for T_C^1, T_D^T and T_C^2 is read as
      reaching it (>=), like the disturbance test of step 2 which the text
      states with ">=".

    **Reading 'literal'** (:class:`IFSMLiteralStepDetector`): the text as
    printed: strict ">" for the three counters, the s0 -> s1 sample not counted,
    and the always-true end condition (s6 as soon as the climbs pass T_C^2). It
    finds 218 / 289 steps on the same files: many steps are lost at s1, where
    the climb from A_T to the peak has only four samples above the threshold.

    Both readings: s2 and s4 are momentary states (they clear a counter and hand
    over to s3 / s5 on the same sample); s3 counts only descents and s5 only
    climbs (the counter the next test uses); the peak / trough tests look one
    sample ahead (A_{k+1}), as printed.

    References
    ----------
    Bi J. et al., Geomatics and Information Science of Wuhan University 2021
    (paper 000), sec. 2.1-2.3, Table 1, Tables 2-3.
    """

    name = "ifsm"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "first_climbs": [POSITIVE_INTEGER],
        "descents": [POSITIVE_INTEGER],
        "second_climbs": [POSITIVE_INTEGER],
        "disturb_descents": [POSITIVE_INTEGER],
        "smoothing_samples": [POSITIVE_INTEGER],
        "diff_threshold_ms2": [NON_NEGATIVE],
        "end_tolerance_ms2": [NON_NEGATIVE],
    }

    def __init__(
        self,
        *,
        reading: str = "reproduce",
        magnitude_threshold_ms2: float = MAGNITUDE_THRESHOLD_MS2,
        diff_threshold_ms2: float = DIFF_THRESHOLD_MS2,
        first_climbs: int = FIRST_CLIMBS,
        descents: int = DESCENTS,
        second_climbs: int = SECOND_CLIMBS,
        disturb_descents: int = DISTURB_DESCENTS,
        end_tolerance_ms2: float = END_TOLERANCE_MS2,
        smoothing_samples: int = SMOOTHING_SAMPLES,
    ):
        self.reading = reading
        self.magnitude_threshold_ms2 = magnitude_threshold_ms2
        self.diff_threshold_ms2 = diff_threshold_ms2
        self.first_climbs = first_climbs
        self.descents = descents
        self.second_climbs = second_climbs
        self.disturb_descents = disturb_descents
        self.end_tolerance_ms2 = end_tolerance_ms2
        self.smoothing_samples = smoothing_samples

    def _core_params(self) -> dict:
        """The keyword arguments of :func:`ifsm_steps` (validated parameters, reading resolved)."""
        params = self._validate_params()
        reading = params.pop("reading")
        if reading not in IFSM_READINGS:
            raise InputError(f"`reading` must be one of {sorted(IFSM_READINGS)}, got {reading!r}.")
        del params["smoothing_samples"]
        count_entry, inclusive, end_condition = IFSM_READINGS[reading]
        return dict(params, count_entry=count_entry, inclusive=inclusive, end_condition=end_condition)

    def detect(self, recording: Recording) -> IFSMStepDetector:
        """Detect steps in ``recording``; results in ``steps_``."""
        rec = as_recording(recording, f"{self.name} step detection")
        params = self._core_params()
        fs = rec.sampling_rate_hz
        A = resample_signal(acc_magnitude(rec), fs, DESIGN_RATE_HZ)
        A = moving_average(A, int(self.smoothing_samples))
        ev = ifsm_steps(A, **params)
        n = rec.n_samples
        t0, kp, kt, te = (map_indices(ev[:, i], DESIGN_RATE_HZ, fs, n) for i in range(4))
        self.steps_: pd.DataFrame = make_step_table(
            t0, kp, te, fs, event="t_end_s", period_s=(ev[:, 3] - ev[:, 0]) / DESIGN_RATE_HZ, trough=kt
        )
        return self


#: lowest recording rate (Hz) ifsm-literal's count holds at (paper 000 records at 50 Hz): the floor rule of
#: :mod:`gaitml.steps._rate` on tyrex (the figures: experiments/reports/tyrex-steps.md, 'rate floors')
LITERAL_RATE_FLOOR_HZ = 15.0


class IFSMLiteralStepDetector(IFSMStepDetector):
    """The IFSM of paper 000 with its text read literally (see :class:`IFSMStepDetector` Notes).

    Parameters
    ----------
    reading : {'literal', 'reproduce'}, default 'literal'
        How to read the printed text (:class:`IFSMStepDetector` Notes).
    magnitude_threshold_ms2 : float, default 9.81
        A_T (Table 1).
    diff_threshold_ms2 : float, default 0.04
        A_D^T (Table 1).
    first_climbs, descents, second_climbs : int, default 4 / 7 / 5
        T_C^1, T_D^T, T_C^2 (Table 1), samples at 50 Hz.
    disturb_descents : int, default 3
        T_C^D (Table 1).
    end_tolerance_ms2 : float, default 0.2
        delta (Table 1).
    smoothing_samples : int, default 5
        Moving average (sec. 2.1), centred, at 50 Hz.

    Attributes
    ----------
    steps_ : DataFrame
        As :class:`IFSMStepDetector`.
    """

    name = "ifsm-literal"
    rate_floor_hz = LITERAL_RATE_FLOOR_HZ

    def __init__(
        self,
        *,
        reading: str = "literal",
        magnitude_threshold_ms2: float = MAGNITUDE_THRESHOLD_MS2,
        diff_threshold_ms2: float = DIFF_THRESHOLD_MS2,
        first_climbs: int = FIRST_CLIMBS,
        descents: int = DESCENTS,
        second_climbs: int = SECOND_CLIMBS,
        disturb_descents: int = DISTURB_DESCENTS,
        end_tolerance_ms2: float = END_TOLERANCE_MS2,
        smoothing_samples: int = SMOOTHING_SAMPLES,
    ):
        super().__init__(
            reading=reading,
            magnitude_threshold_ms2=magnitude_threshold_ms2,
            diff_threshold_ms2=diff_threshold_ms2,
            first_climbs=first_climbs,
            descents=descents,
            second_climbs=second_climbs,
            disturb_descents=disturb_descents,
            end_tolerance_ms2=end_tolerance_ms2,
            smoothing_samples=smoothing_samples,
        )
