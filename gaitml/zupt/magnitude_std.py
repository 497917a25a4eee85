"""Magnitude-and-std ZUPT detector (``magnitude-std``): four conditions on acc and gyro magnitude and std.

Paper 001's baseline "method 2" (formerly registered as ``method2``).

Paper 001 (Dai et al., 2018), introduction and sec. 3, citing its ref. [11]
(Huang et al., 2017): "acc magnitude + acc standard deviation + gyro magnitude +
gyro standard deviation", each compared with a fixed threshold; all four must
hold (a multi-condition AND, as in Jimenez et al. 2009's C1-C3).
"""

from __future__ import annotations

import numpy as np

from gaitml.recording import Recording
from gaitml.signal import magnitude
from gaitml.zupt._base import FixedThresholdZuptDetector
from gaitml.zupt._intervals import acc_gyr_window, centered_sums

__all__ = ["MagnitudeStdZuptDetector", "magnitude_std_zupts"]

#: |a| band (m/s^2): Jimenez et al. 2009 condition C1, 9 < |a| < 11 (paper 001 prints no values).
DEFAULT_ACC_MIN_MS2 = 9.0
DEFAULT_ACC_MAX_MS2 = 11.0
#: Window std of |a| below 1.0 m/s^2 (our choice).
DEFAULT_ACC_STD_MS2 = 1.0
#: |w| below 50 deg/s = 0.873 rad/s: Jimenez et al. 2009 condition C3.
DEFAULT_GYR_MAX_RADS = 50.0 * np.pi / 180.0
#: Window std of |w| below 0.3 rad/s (our choice).
DEFAULT_GYR_STD_RADS = 0.3
#: Half-window (s), the same 0.05 s as the pseudo-std detector.
DEFAULT_HALF_WINDOW_S = 0.05


def _window_std(x: np.ndarray, half: int) -> np.ndarray:
    sums, counts = centered_sums(np.column_stack([x, x * x]), half)
    mean = sums[:, 0] / counts
    return np.sqrt(np.maximum(sums[:, 1] / counts - mean * mean, 0.0))


def magnitude_std_zupts(
    acc_ms2: np.ndarray,
    gyr_rads: np.ndarray,
    half_window_samples: int,
    *,
    acc_min_ms2: float = DEFAULT_ACC_MIN_MS2,
    acc_max_ms2: float = DEFAULT_ACC_MAX_MS2,
    acc_std_ms2: float = DEFAULT_ACC_STD_MS2,
    gyr_max_rads: float = DEFAULT_GYR_MAX_RADS,
    gyr_std_rads: float = DEFAULT_GYR_STD_RADS,
) -> np.ndarray:
    """Zero velocity where all four conditions hold at sample i.

    ``acc_min < |a(i)| < acc_max`` and ``std(|a|) < acc_std`` and ``|w(i)| < gyr_max``
    and ``std(|w|) < gyr_std``, the stds over the centred window ``[i - s, i + s]``
    (truncated at the edges).
    """
    a, w, s = acc_gyr_window(acc_ms2, gyr_rads, half_window_samples)
    am = magnitude(a)
    wm = magnitude(w)
    return (
        (am > acc_min_ms2)
        & (am < acc_max_ms2)
        & (_window_std(am, s) < acc_std_ms2)
        & (wm < gyr_max_rads)
        & (_window_std(wm, s) < gyr_std_rads)
    )


class MagnitudeStdZuptDetector(FixedThresholdZuptDetector):
    """Magnitude-and-std detector, paper 001's method 2 (four fixed-threshold conditions, AND).

    Parameters
    ----------
    acc_min_ms2, acc_max_ms2 : float, default 9.0 / 11.0
        |a| band (m/s^2, Jimenez et al. 2009 C1).
    acc_std_ms2 : float, default 1.0
        Window std of |a| (m/s^2).
    gyr_max_rads : float, default 50 deg/s
        |w| bound (rad/s, Jimenez et al. 2009 C3).
    gyr_std_rads : float, default 0.3
        Window std of |w| (rad/s).
    half_window_s : float, default 0.05
        Half-window in seconds.

    Notes
    -----
    Paper 001 does not print the thresholds of its ref. [11]; the defaults are
    stated above (two from Jimenez et al. 2009, two ours). ``statistic_`` is |w|.
    No ``fit`` (fixed thresholds, as compared in paper 001 Table 1).
    """

    name = "magnitude-std"

    def __init__(
        self,
        *,
        acc_min_ms2: float = DEFAULT_ACC_MIN_MS2,
        acc_max_ms2: float = DEFAULT_ACC_MAX_MS2,
        acc_std_ms2: float = DEFAULT_ACC_STD_MS2,
        gyr_max_rads: float = DEFAULT_GYR_MAX_RADS,
        gyr_std_rads: float = DEFAULT_GYR_STD_RADS,
        half_window_s: float = DEFAULT_HALF_WINDOW_S,
    ):
        self.acc_min_ms2 = acc_min_ms2
        self.acc_max_ms2 = acc_max_ms2
        self.acc_std_ms2 = acc_std_ms2
        self.gyr_max_rads = gyr_max_rads
        self.gyr_std_rads = gyr_std_rads
        self.half_window_s = half_window_s

    def _mask(self, recording: Recording):
        mask, gyr = self._thresholded(
            recording, "the magnitude-std detector (acc/gyro magnitude and std, paper 001 method 2)", magnitude_std_zupts
        )
        return mask, magnitude(gyr)
