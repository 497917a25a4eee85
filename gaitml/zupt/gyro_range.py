"""Gyro-range ZUPT detector (``gyro-range``): three-axis gyro range OR acceleration-magnitude maximum.

Paper 001's baseline "method 1" (formerly registered as ``method1``).

Paper 001 (Dai et al., 2018), introduction and sec. 3, citing its ref. [8]
(Wan et al., 2015): over a sampling window, the range (max - min) of each gyro
axis and the maximum of the acceleration magnitude are compared with fixed
thresholds and the two decisions are combined with a logical OR ("经过'或'运算",
which the paper says lowers missed detections but raises false ones).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d

from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording
from gaitml.signal import magnitude
from gaitml.zupt._base import FixedThresholdZuptDetector
from gaitml.zupt._intervals import acc_gyr_window

__all__ = ["GyroRangeZuptDetector", "gyro_range_zupts", "DEFAULT_GYR_RANGE_RADS", "DEFAULT_ACC_MAX_MS2"]

#: Threshold on the largest per-axis gyro range in the window (rad/s). Neither paper 001
#: nor this package's sources print the values of ref. [8]; 0.5 rad/s (29 deg/s) is our choice.
DEFAULT_GYR_RANGE_RADS = 0.5
#: Threshold on the window maximum of |a| (m/s^2): g + 0.5 m/s^2 (our choice, see above).
DEFAULT_ACC_MAX_MS2 = GRAVITY_MS2 + 0.5
#: Half-window (s), the same 0.05 s as the pseudo-std detector.
DEFAULT_HALF_WINDOW_S = 0.05


def _window_max(x: np.ndarray, half: int) -> np.ndarray:
    return maximum_filter1d(x, size=2 * half + 1, axis=-1, mode="nearest")


def _window_min(x: np.ndarray, half: int) -> np.ndarray:
    return minimum_filter1d(x, size=2 * half + 1, axis=-1, mode="nearest")


def gyro_range_zupts(
    acc_ms2: np.ndarray,
    gyr_rads: np.ndarray,
    half_window_samples: int,
    *,
    gyr_range_rads: float = DEFAULT_GYR_RANGE_RADS,
    acc_max_ms2: float = DEFAULT_ACC_MAX_MS2,
):
    """Zero velocity where ``max_axis range(gyr) < gyr_range_rads`` OR ``max |a| < acc_max_ms2``.

    Both statistics over the centred window ``[i - s, i + s]`` (edges: the
    window is clipped to the recording, ``scipy.ndimage`` ``mode='nearest'``).

    Returns
    -------
    mask : ndarray of bool, shape (n,)
    gyr_range : ndarray, shape (n,)  largest per-axis gyro range (rad/s)
    acc_max : ndarray, shape (n,)  window maximum of |a| (m/s^2)
    """
    a, w, s = acc_gyr_window(acc_ms2, gyr_rads, half_window_samples)
    wt = np.ascontiguousarray(w.T)  # filter contiguous rows (3, n): much faster than strided columns
    gyr_range = (_window_max(wt, s) - _window_min(wt, s)).max(axis=0)
    acc_max = _window_max(magnitude(a), s)
    return (gyr_range < gyr_range_rads) | (acc_max < acc_max_ms2), gyr_range, acc_max


class GyroRangeZuptDetector(FixedThresholdZuptDetector):
    """Gyro-range detector, paper 001's method 1 (gyro range OR |a| maximum, fixed thresholds).

    Parameters
    ----------
    gyr_range_rads : float, default 0.5
        Threshold on the largest per-axis gyro range in the window (rad/s).
    acc_max_ms2 : float, default g + 0.5
        Threshold on the window maximum of |a| (m/s^2).
    half_window_s : float, default 0.05
        Half-window in seconds (s = round(0.05 fs)).

    Notes
    -----
    The thresholds of ref. [8] are not printed in paper 001; the defaults are
    ours and stated above. The combination is OR, as paper 001 describes it.
    ``statistic_`` is the gyro range. No ``fit``: paper 001 uses it with fixed
    thresholds (that is the point of its comparison, Table 1).
    """

    name = "gyro-range"

    def __init__(
        self,
        *,
        gyr_range_rads: float = DEFAULT_GYR_RANGE_RADS,
        acc_max_ms2: float = DEFAULT_ACC_MAX_MS2,
        half_window_s: float = DEFAULT_HALF_WINDOW_S,
    ):
        self.gyr_range_rads = gyr_range_rads
        self.acc_max_ms2 = acc_max_ms2
        self.half_window_s = half_window_s

    def _mask(self, recording: Recording):
        (mask, gyr_range, acc_max), _ = self._thresholded(
            recording, "the gyro-range detector (gyro range + |a| maximum, paper 001 method 1)", gyro_range_zupts
        )
        self.acc_max_ms2_series_ = acc_max
        return mask, gyr_range
