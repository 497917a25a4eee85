"""One uniformly sampled IMU recording (:class:`Recording`) and the checks that build it.

- :mod:`gaitml.recording.container`: the :class:`Recording` container and its constructors;
- :mod:`gaitml.recording.units`: unit judgement (g vs m/s^2, deg/s vs rad/s) and conversion;
- :mod:`gaitml.recording.ranges`: shapes, finite values, values beyond any sensor's range;
- :mod:`gaitml.recording.timestamps`: increasing times, plausible rates, gaps;
- :mod:`gaitml.recording.resampling`: timestamped samples onto a uniform grid.
"""

from __future__ import annotations

from gaitml.recording.container import Recording
from gaitml.recording.ranges import as_2d3, check_finite, check_range, check_ranges
from gaitml.recording.resampling import resample_uniform
from gaitml.recording.timestamps import (
    GAP_FACTOR,
    MAX_BRIDGE_FACTOR,
    MAX_BRIDGE_S,
    MAX_RATE_HZ,
    MIN_RATE_HZ,
    check_rate,
    check_timed_samples,
    max_bridge_s,
    recorded_rate_hz,
    split_points,
)
from gaitml.recording.units import check_acc_unit, check_gyr_unit, check_units, convert_units, note_conversions

__all__ = [
    "Recording",
    "check_acc_unit",
    "check_gyr_unit",
    "check_range",
    "check_rate",
    "max_bridge_s",
    "recorded_rate_hz",
    "resample_uniform",
    "split_points",
    "MIN_RATE_HZ",
    "MAX_RATE_HZ",
    "MAX_BRIDGE_S",
    "MAX_BRIDGE_FACTOR",
    "GAP_FACTOR",
    "as_2d3",
    "check_finite",
    "check_ranges",
    "check_timed_samples",
    "check_units",
    "convert_units",
    "note_conversions",
]
