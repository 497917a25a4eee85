"""Acceleration-differential finite state machine (AD-FSM), the baseline of paper 000.

Paper 000 (Bi et al. 2021) sec. 2 compares IFSM with the AD-FSM of Wang Gechao et
al. (its ref. [24], J. Frontiers of Computer Science and Technology 2016): three
states, a step recognised from the *counts* of positive and negative
acceleration differences (no amplitude threshold, which avoids pseudo-peaks),
and the step completed on entering the trough state (which is why paper 000
finds its step times late). Paper 000 gives no parameter values for it; the
counts below are ours (stated as defaults) and the preprocessing is paper 000's
(|acc|, 5-sample moving average at 50 Hz) rather than ref. [24]'s Kalman filter.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import NON_NEGATIVE, POSITIVE_INTEGER
from gaitml.recording import Recording
from gaitml.signal import moving_average
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import (
    acc_magnitude,
    as_recording,
    map_indices,
    resample_signal,
    segment_argmax,
)
from gaitml.steps._table import make_step_table

__all__ = ["RATE_FLOOR_HZ", "ADFSMStepDetector", "adfsm_steps"]

#: our choice (paper 000 gives none): consecutive rising differences that confirm a climb (50 Hz samples)
MIN_RISES = 5
#: our choice: falling differences that make a trough a step (50 Hz samples)
MIN_FALLS = 5
#: |difference| up to this is "flat" (neither counts nor breaks a run), m/s^2: we reuse paper 000's
#: Table 1 A_diff = 0.04 so sensor noise of a phone at rest does not count as steps
FLAT_DIFF_MS2 = 0.04
#: paper 000 sec. 2.1 preprocessing: 5-sample moving average at 50 Hz
SMOOTHING_SAMPLES = 5
DESIGN_RATE_HZ = 50.0


def adfsm_steps(
    A: np.ndarray, *, min_rises: int = MIN_RISES, min_falls: int = MIN_FALLS, flat_diff_ms2: float = FLAT_DIFF_MS2
) -> np.ndarray:
    """The AD-FSM over a smoothed magnitude ``A`` (m/s^2, 50 Hz samples).

    States: 0 valley (count consecutive rises; a fall clears the count; at
    ``min_rises`` -> 1), 1 rising (a fall -> 2 with one fall counted), 2 falling
    (count falls; a rise ends the descent: with at least ``min_falls`` falls the
    previous sample was a trough and a step is counted -> 0 with one rise
    counted, otherwise the fall was a pseudo-peak -> 1). Flat differences
    (``|d| <= flat_diff_ms2``) change nothing.

    The signs of the differences are computed with numpy and grouped into runs
    (flat differences dropped); the machine then steps once per run, which gives
    the same result as stepping once per sample (``tests/steps/reference_fsm.py``).

    Returns
    -------
    int array (n_steps, 2): trough sample and completion sample.
    """
    A = np.asarray(A, dtype=float)
    if len(A) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    d = np.diff(A)
    sgn = np.where(d > flat_diff_ms2, 1, np.where(d < -flat_diff_ms2, -1, 0))
    nz = np.flatnonzero(sgn)
    if len(nz) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    sv = sgn[nz]
    brk = np.flatnonzero(sv[1:] != sv[:-1]) + 1
    starts = np.concatenate([[0], brk])
    lens = np.diff(np.concatenate([starts, [len(sv)]])).tolist()
    signs = sv[starts].tolist()
    first_k = (nz[starts] + 1).tolist()  # sample index k of the first difference of each run
    s, pc, nc = 0, 0, 0
    out = []
    for sign, length, k in zip(signs, lens, first_k, strict=True):
        if sign > 0:
            if s == 0:
                pc += length
                if pc >= min_rises:
                    s = 1
            elif s == 2:
                if nc >= min_falls:
                    out.append((k - 1, k))
                    pc = length
                    s = 1 if pc >= min_rises else 0
                else:
                    s = 1
        else:
            if s == 0:
                pc = 0
            elif s == 1:
                s, nc = 2, length
            else:
                nc += length
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)


#: lowest recording rate (Hz) adfsm's count holds at (paper 000 records at 50 Hz): the floor rule of
#: :mod:`gaitml.steps._rate` on tyrex, the highest floor any leave-one-person-out fold gives (the figures:
#: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 30.0


class ADFSMStepDetector(BaseStepDetector):
    """AD-FSM step detector (paper 000's baseline, its ref. [24]).

    Parameters
    ----------
    min_rises, min_falls : int, default 5 / 5
        Difference counts (samples at 50 Hz) that confirm a climb and a descent.
        Our values: paper 000 does not print those of ref. [24].
    flat_diff_ms2 : float, default 0.04
        Differences with ``|d|`` up to this are flat (paper 000 Table 1's A_diff,
        reused here so a phone at rest does not count steps).
    smoothing_samples : int, default 5
        Moving average at 50 Hz (paper 000 sec. 2.1).

    Attributes
    ----------
    steps_ : DataFrame
        ``start`` = previous completion (first step: its climb start), ``peak`` =
        maximum between, ``end`` = completion sample (one after the trough, the
        first rising difference); ``period_s`` = completion-to-completion
        interval (first step: ``end - start``); ``trough``.
        ``attrs['event'] = 't_end_s'``.

    Notes
    -----
    A recording at another rate is resampled to 50 Hz (the counts are 50 Hz
    samples) and the indices are mapped back.

    References
    ----------
    Bi J. et al. 2021 (paper 000), sec. 2 and Table 2; Wang G. et al., Step
    Counting Algorithm Based on Finite State Machine Using Acceleration
    Differential, J. Frontiers of Computer Science and Technology 2016.
    """

    name = "adfsm"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "min_rises": [POSITIVE_INTEGER],
        "min_falls": [POSITIVE_INTEGER],
        "smoothing_samples": [POSITIVE_INTEGER],
        "flat_diff_ms2": [NON_NEGATIVE],
    }

    def __init__(
        self,
        *,
        min_rises: int = MIN_RISES,
        min_falls: int = MIN_FALLS,
        flat_diff_ms2: float = FLAT_DIFF_MS2,
        smoothing_samples: int = SMOOTHING_SAMPLES,
    ):
        self.min_rises = min_rises
        self.min_falls = min_falls
        self.flat_diff_ms2 = flat_diff_ms2
        self.smoothing_samples = smoothing_samples

    def detect(self, recording: Recording) -> ADFSMStepDetector:
        """Detect steps in ``recording``; results in ``steps_``."""
        params = self._validate_params()
        smoothing = int(params.pop("smoothing_samples"))
        rec = as_recording(recording, "adfsm step detection")
        fs = rec.sampling_rate_hz
        A = moving_average(resample_signal(acc_magnitude(rec), fs, DESIGN_RATE_HZ), smoothing)
        ev = adfsm_steps(A, **params)
        trough, end = ev[:, 0], ev[:, 1]
        start = np.empty_like(end)
        if len(end):
            start[1:] = end[:-1]
            start[0] = max(0, end[0] - int(np.median(np.diff(end))) if len(end) > 1 else 0)
        peak = segment_argmax(A, start, end)
        n = rec.n_samples
        m = [map_indices(x, DESIGN_RATE_HZ, fs, n) for x in (start, peak, end, trough)]
        self.steps_: pd.DataFrame = make_step_table(
            m[0], m[1], m[2], fs, event="t_end_s", period_s=(end - start) / DESIGN_RATE_HZ, trough=m[3]
        )
        return self
