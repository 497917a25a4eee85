"""Single-peak step detection with zero points (paper 003, sec. 2).

Deng et al., "A PDR algorithm based on human motion recognition", J. Chinese
Inertial Technology 2021, sec. 2.1-2.2: the gravity-free magnitude
``a = |acc| - g`` (eq. 1) is smoothed with a moving average of N = 3 samples;
every valid peak above sigma1 = 2 m/s^2, at least sigma2 = 15 samples apart, is
one step (no trough is needed, so side and backward steps work). Around each
peak the left zero point is the first zero crossing searching backwards (at most
12 samples), the right zero point the second zero crossing searching forwards
(at most 25 samples); the step spans the two zero points and gives the step
period (and frequency).

Reading of the zero points (documented choice): the right zero point is the
*second* crossing after the peak, so a step spans a whole cycle of the
gravity-free magnitude: up-crossing (left zero point) -> peak -> down-crossing ->
trough -> up-crossing (right zero point), about 0.5 s at a normal walk, the same
as the interval between consecutive peaks. On phone data (IFSM, 50 Hz) the
3-sample smoothed magnitude often flips sign for only 1-3 samples (20-60 ms)
just after the peak (a double hump of the heel strike); counting those flips as
zero points ends the "step" in mid-cycle (median period 0.28 s for steps 0.52 s
apart on acceleration_flat_holding_2.xlsx). The paper bounds the search "to
suppress noise" but does not say how brief flips are treated; we count a zero
crossing only when the new sign then lasts at least ``min_lobe_s`` = 0.1 s
(5 samples at 50 Hz; real lobes of a step last >= 10 samples, the flips <= 3),
and drop a lasting crossing that returns to the sign already held. ``min_lobe_s``
at one sample gives the literal every-crossing rule. Peaks and thus step counts
do not depend on the zero points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd
import scipy.signal

from gaitml._base import NON_NEGATIVE, POSITIVE
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.signal import moving_average
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._common import acc_magnitude, as_recording, check_positive
from gaitml.steps._table import make_step_table

__all__ = ["RATE_FLOOR_HZ", "SinglePeakStepDetector", "single_peak_steps", "zero_points"]

#: paper 003 sec. 2.2: peak threshold sigma1 = 2 m/s^2
PEAK_THRESHOLD_MS2 = 2.0
#: paper 003 sec. 2.2: sigma2 = 15 samples at 50 Hz = 0.3 s between peaks
MIN_PEAK_DISTANCE_S = 15 / 50.0
#: paper 003 sec. 2.2: left zero point searched at most 12 samples at 50 Hz = 0.24 s back
LEFT_ZERO_SEARCH_S = 12 / 50.0
#: paper 003 sec. 2.2: right zero point searched at most 25 samples at 50 Hz = 0.5 s forward
RIGHT_ZERO_SEARCH_S = 25 / 50.0
#: paper 003 sec. 2.1: moving average of N = 3 samples at 50 Hz = 0.06 s
SMOOTHING_S = 3 / 50.0
#: Our choice (not in paper 003): a zero crossing counts only when the new sign lasts
#: at least this long (see the module notes); 0.1 s = 5 samples at 50 Hz.
MIN_LOBE_S = 0.1
#: paper 003 eq. (1): g = 9.8 m/s^2
PAPER_GRAVITY_MS2 = 9.8


def _samples(seconds: float, fs: float, minimum: int = 1) -> int:
    return max(minimum, int(round(seconds * fs)))


def lasting_crossings(a: np.ndarray, min_lobe_samples: int = 1) -> np.ndarray:
    """Zero crossings of ``a`` whose new sign lasts at least ``min_lobe_samples``.

    A crossing between samples ``j - 1`` and ``j`` is reported at ``j`` (the first
    sample of the new sign). Brief sign flips (shorter runs) are ignored, and of
    consecutive lasting crossings into the same sign only the first is kept, so the
    result alternates between down- and up-crossings. ``min_lobe_samples = 1``
    gives every crossing.
    """
    a = np.asarray(a, dtype=float)
    sign = a >= 0
    cross = np.flatnonzero(sign[1:] != sign[:-1]) + 1
    m = max(1, int(min_lobe_samples))
    if m == 1 or not len(cross):
        return cross
    run = np.diff(np.append(cross, len(a)))
    keep = cross[run >= m]
    if not len(keep):
        return keep
    new = sign[keep]
    # first of each group of lasting crossings into the same sign; the very first must
    # leave the sign the signal starts with
    first = np.empty(len(keep), dtype=bool)
    first[0] = new[0] != sign[0]
    first[1:] = new[1:] != new[:-1]
    return keep[first]


def zero_points(
    a: np.ndarray, peaks: np.ndarray, left_max_samples: int, right_max_samples: int, min_lobe_samples: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Left and right zero points of each peak of a zero-mean signal (paper 003 sec. 2.2).

    A zero crossing between samples ``j - 1`` and ``j`` is reported at ``j`` (the
    first sample of the new sign); only crossings whose new sign lasts at least
    ``min_lobe_samples`` count (:func:`lasting_crossings`; 1 = every crossing).
    Left: the nearest crossing at or before the
    peak, at most ``left_max_samples`` back; right: the second crossing after the
    peak, at most ``right_max_samples`` forward. Where none is found within the
    range, the search limit itself is returned (clipped to the signal) and the
    corresponding ``found`` flag is False.

    Returns
    -------
    left, right : int arrays (n_peaks,)
        Sample indices; ``right`` is used as the exclusive step end.
    left_found, right_found : bool arrays
    """
    a = np.asarray(a, dtype=float)
    n = len(a)
    peaks = np.asarray(peaks, dtype=np.int64)
    cross = lasting_crossings(a, min_lobe_samples)
    # left: last crossing <= peak
    i_left = np.searchsorted(cross, peaks, side="right") - 1
    left_c = np.where(i_left >= 0, cross[np.clip(i_left, 0, max(len(cross) - 1, 0))] if len(cross) else 0, -(10**9))
    left_found = (i_left >= 0) & (peaks - left_c <= left_max_samples)
    left = np.where(left_found, left_c, np.maximum(peaks - left_max_samples, 0))
    # right: second crossing > peak
    i_right = np.searchsorted(cross, peaks, side="right") + 1
    has = i_right < len(cross)
    right_c = np.where(has, cross[np.clip(i_right, 0, max(len(cross) - 1, 0))] if len(cross) else 0, 10**12)
    right_found = has & (right_c - peaks <= right_max_samples)
    right = np.where(right_found, right_c, np.minimum(peaks + right_max_samples, n))
    return left.astype(np.int64), right.astype(np.int64), left_found, right_found


def single_peak_steps(
    acc_mag_ms2: np.ndarray,
    sampling_rate_hz: float,
    *,
    peak_threshold_ms2: float = PEAK_THRESHOLD_MS2,
    min_peak_distance_s: float = MIN_PEAK_DISTANCE_S,
    left_zero_search_s: float = LEFT_ZERO_SEARCH_S,
    right_zero_search_s: float = RIGHT_ZERO_SEARCH_S,
    smoothing_s: float = SMOOTHING_S,
    gravity_ms2: float = PAPER_GRAVITY_MS2,
    min_lobe_s: float = MIN_LOBE_S,
) -> dict[str, np.ndarray]:
    """Detect steps in an acceleration magnitude (gravity included) by single peaks.

    Parameters
    ----------
    acc_mag_ms2 : ndarray (n,)
        |acc| in m/s^2.
    sampling_rate_hz : float
    peak_threshold_ms2, min_peak_distance_s, left_zero_search_s, right_zero_search_s, smoothing_s
        Paper 003 sec. 2 values converted from samples at 50 Hz to seconds.
    gravity_ms2 : float
        g subtracted from the magnitude (paper 003 eq. 1: 9.8).
    min_lobe_s : float
        A zero crossing counts only when the new sign lasts this long (our choice,
        see the module notes; 0 counts every crossing).

    Returns
    -------
    dict with ``peak``, ``start`` (left zero point), ``end`` (right zero point,
    exclusive), ``left_found``, ``right_found`` (int / bool arrays) and ``a``
    (the smoothed gravity-free magnitude).
    """
    x = np.asarray(acc_mag_ms2, dtype=float)
    if x.ndim != 1:
        raise InputError(f"`acc_mag_ms2` must be 1-D, got shape {x.shape}.")
    fs = check_positive("sampling_rate_hz", sampling_rate_hz)
    check_positive("min_peak_distance_s", min_peak_distance_s)
    check_positive("smoothing_s", smoothing_s)
    check_positive("left_zero_search_s", left_zero_search_s, allow_zero=True)
    check_positive("right_zero_search_s", right_zero_search_s, allow_zero=True)
    check_positive("min_lobe_s", min_lobe_s, allow_zero=True)
    a = moving_average(x - gravity_ms2, _samples(smoothing_s, fs))
    peaks, _ = scipy.signal.find_peaks(a, height=peak_threshold_ms2, distance=_samples(min_peak_distance_s, fs))
    left, right, lf, rf = zero_points(
        a, peaks, _samples(left_zero_search_s, fs, 0), _samples(right_zero_search_s, fs, 0), _samples(min_lobe_s, fs, 1)
    )
    return {"peak": peaks.astype(np.int64), "start": left, "end": right, "left_found": lf, "right_found": rf, "a": a}


#: lowest recording rate (Hz) single-peak's count holds at: paper 003 designs it at 50 Hz (sec. 2, its
#: windows are samples at 50 Hz), and the floor rule of :mod:`gaitml.steps._rate` on tyrex gives the same (the
#: figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 50.0


class SinglePeakStepDetector(BaseStepDetector):
    """Single-peak step detector with zero points (paper 003 sec. 2.2).

    Parameters
    ----------
    peak_threshold_ms2 : float, default 2.0
        sigma1 (paper 003 sec. 2.2), on ``|acc| - g`` after smoothing.
    min_peak_distance_s : float, default 0.3
        sigma2 = 15 samples at 50 Hz.
    left_zero_search_s, right_zero_search_s : float, default 0.24 / 0.5
        Zero-point search ranges: 12 and 25 samples at 50 Hz.
    smoothing_s : float, default 0.06
        Moving-average length: N = 3 samples at 50 Hz (rounded to samples at the
        recording's rate; centred window).
    gravity_ms2 : float, default 9.8
        g of paper 003 eq. (1).
    min_lobe_s : float, default 0.1
        Zero crossings count only when the new sign lasts this long (our reading;
        brief flips after the heel-strike peak would end the step mid-cycle).

    Attributes
    ----------
    steps_ : DataFrame
        DESIGN step table; ``start``/``end`` are the left/right zero points,
        ``peak`` the peak sample, ``period_s = (end - start) / fs`` (one step
        cycle, up-crossing to up-crossing: about the interval between steps), plus
        ``peak_ms2`` (smoothed |acc| - g at the peak), ``zero_found`` (both zero
        points found inside their search range). ``attrs['event'] = 't_peak_s'``.

    Notes
    -----
    Parameters are in physical units so other sampling rates work. Peaks come
    from :func:`scipy.signal.find_peaks` with ``height`` and ``distance``: within
    ``min_peak_distance_s`` the higher peak wins (our reading of "valid peaks at
    least sigma2 apart"). On the paper 000 data (50 Hz) it finds exactly 284 and
    319 steps.

    References
    ----------
    Deng et al., J. Chinese Inertial Technology 2021 (paper 003), sec. 2.1-2.2.
    """

    name = "single-peak"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "min_peak_distance_s": [POSITIVE],
        "smoothing_s": [POSITIVE],
        "left_zero_search_s": [NON_NEGATIVE],
        "right_zero_search_s": [NON_NEGATIVE],
        "min_lobe_s": [NON_NEGATIVE],
    }

    def __init__(
        self,
        *,
        peak_threshold_ms2: float = PEAK_THRESHOLD_MS2,
        min_peak_distance_s: float = MIN_PEAK_DISTANCE_S,
        left_zero_search_s: float = LEFT_ZERO_SEARCH_S,
        right_zero_search_s: float = RIGHT_ZERO_SEARCH_S,
        smoothing_s: float = SMOOTHING_S,
        gravity_ms2: float = PAPER_GRAVITY_MS2,
        min_lobe_s: float = MIN_LOBE_S,
    ):
        self.peak_threshold_ms2 = peak_threshold_ms2
        self.min_peak_distance_s = min_peak_distance_s
        self.left_zero_search_s = left_zero_search_s
        self.right_zero_search_s = right_zero_search_s
        self.smoothing_s = smoothing_s
        self.gravity_ms2 = gravity_ms2
        self.min_lobe_s = min_lobe_s

    def detect(self, recording: Recording) -> SinglePeakStepDetector:
        """Detect steps in ``recording``; results in ``steps_``."""
        self._validate_params()
        rec = as_recording(recording, "single-peak step detection")
        fs = rec.sampling_rate_hz
        r = single_peak_steps(acc_magnitude(rec), fs, **self._validate_params())
        self.steps_: pd.DataFrame = make_step_table(
            r["start"],
            r["peak"],
            r["end"],
            fs,
            event="t_peak_s",
            peak_ms2=r["a"][r["peak"]],
            zero_found=r["left_found"] & r["right_found"],
        )
        return self
