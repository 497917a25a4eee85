"""Signal utilities: magnitude, smoothing, Butterworth filters, strided windows, gravity, gyroscope bias, the walker's path from a tracked phone."""

from gaitml.signal._basic import bandpass, butter_filter, centered_window_sums, lowpass, magnitude, moving_average
from gaitml.signal._gyro_bias import (
    GyroBias,
    StillWindows,
    estimate_gyro_bias,
    gyro_bias_from_still,
    gyro_bias_from_windows,
    gyro_still_windows,
    read_gyro_bias_json,
    remove_gyro_bias,
    steady_tilt_mask,
)
from gaitml.signal._orientation import gravity_components, gravity_direction, tilt_angles
from gaitml.signal._track import BODY_CUTOFF_HZ, body_track, uniform_track
from gaitml.signal._windows import sliding_windows, window_params, window_starts

__all__ = [
    "BODY_CUTOFF_HZ",
    "body_track",
    "uniform_track",
    "bandpass",
    "butter_filter",
    "centered_window_sums",
    "GyroBias",
    "StillWindows",
    "estimate_gyro_bias",
    "gyro_bias_from_still",
    "gyro_bias_from_windows",
    "read_gyro_bias_json",
    "remove_gyro_bias",
    "gravity_components",
    "gravity_direction",
    "lowpass",
    "magnitude",
    "moving_average",
    "sliding_windows",
    "steady_tilt_mask",
    "gyro_still_windows",
    "tilt_angles",
    "window_params",
    "window_starts",
]
