"""Per-sample loop implementations of the step FSMs: the test references of the package's fast cores.

Straightforward loops over samples, one state transition at a time, as the papers
describe the machines. The package keeps only the fast implementations
(:func:`gaitml.steps.ifsm.ifsm_steps`, :func:`gaitml.steps.adfsm.adfsm_steps`); the
equality tests run both on random signals. Not for production use (much slower).
"""

from __future__ import annotations

import numpy as np

from gaitml.steps.adfsm import FLAT_DIFF_MS2, MIN_FALLS, MIN_RISES
from gaitml.steps.ifsm import (
    DESCENTS,
    DIFF_THRESHOLD_MS2,
    DISTURB_DESCENTS,
    END_TOLERANCE_MS2,
    FIRST_CLIMBS,
    MAGNITUDE_THRESHOLD_MS2,
    SECOND_CLIMBS,
    _check_reading,
)

__all__ = ["adfsm_steps_loop", "ifsm_steps_loop"]


def ifsm_steps_loop(
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
    """The IFSM as a plain per-sample loop (reference for :func:`gaitml.steps.ifsm.ifsm_steps`).

    Returns an int array (n_steps, 4): ``t0`` (s0 -> s1), peak (s2), trough (s4)
    and ``t_e`` (s6) sample of each step. See :func:`gaitml.steps.ifsm.ifsm_steps` for the states.
    """
    _check_reading(count_entry, inclusive, end_condition)
    A = np.asarray(A, dtype=float).tolist()
    n = len(A)
    off = 0 if inclusive else 1
    c1, cd, c2 = first_climbs + off, descents + off, second_climbs + off
    at, ad = magnitude_threshold_ms2, diff_threshold_ms2
    lo_end = at - end_tolerance_ms2
    s = 0
    tc = td = 0
    t0 = kp = kt = 0
    out = []
    for k in range(1, n - 1):
        a = A[k]
        d = a - A[k - 1]
        if s == 0:
            tc = td = 0
            if a > at:
                s, t0 = 1, k
                if not count_entry:
                    continue
        if s == 1:
            if d > ad:
                tc += 1
            elif d < -ad:
                td += 1
            if td >= disturb_descents:  # noise: back to s0
                s = 0
            elif tc >= c1 and a > A[k - 1] and a > A[k + 1]:  # s2 peak, then s3
                s, td, kp = 3, 0, k
        elif s == 3:
            if d < -ad:
                td += 1
            if td >= cd and a < A[k - 1] and a < A[k + 1]:  # s4 trough, then s5
                s, tc, kt = 5, 0, k
        elif s == 5:
            if d > ad:
                tc += 1
            if tc >= c2 and (end_condition == "always" or a > lo_end):  # s6: one step
                out.append((t0, kp, kt, k))
                s = 0
    return np.asarray(out, dtype=np.int64).reshape(-1, 4)


def adfsm_steps_loop(
    A: np.ndarray, *, min_rises: int = MIN_RISES, min_falls: int = MIN_FALLS, flat_diff_ms2: float = FLAT_DIFF_MS2
) -> np.ndarray:
    """AD-FSM as a plain per-sample loop (reference for :func:`gaitml.steps.adfsm.adfsm_steps`).

    States: 0 valley (count consecutive rises; a fall clears the count; at
    ``min_rises`` -> 1), 1 rising (a fall -> 2 with one fall counted), 2 falling
    (count falls; a rise ends the descent: with at least ``min_falls`` falls the
    previous sample was a trough and a step is counted -> 0 with one rise
    counted, otherwise the fall was a pseudo-peak -> 1). Flat differences
    (``|d| <= flat_diff_ms2``) change nothing.

    Returns int array (n_steps, 2): trough sample and completion sample.
    """
    A = np.asarray(A, dtype=float).tolist()
    s, pc, nc = 0, 0, 0
    out = []
    for k in range(1, len(A)):
        d = A[k] - A[k - 1]
        if d > flat_diff_ms2:
            if s == 0:
                pc += 1
                if pc >= min_rises:
                    s = 1
            elif s == 2:
                if nc >= min_falls:
                    out.append((k - 1, k))
                    s, pc = 0, 1
                    if pc >= min_rises:
                        s = 1
                else:
                    s = 1
        elif d < -flat_diff_ms2:
            if s == 0:
                pc = 0
            elif s == 1:
                s, nc = 2, 1
            else:
                nc += 1
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)
