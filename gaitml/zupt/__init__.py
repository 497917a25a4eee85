"""Zero-velocity (ZUPT) detectors, one algorithm per module, behind one API.

Detectors (DESIGN sec. 4/5 names): ``pseudo-std`` (paper 001), ``magnitude``
(paper 004), ``gyro-range`` and ``magnitude-std`` (paper 001's baselines, its
"method 1" and "method 2", named by the statistics they threshold; the old names
``method1`` / ``method2`` are still accepted by :func:`get_detector`, deprecated)
and ``shoe`` (Skog et al. 2010). Each has ``detect(recording) -> self`` setting
``per_sample_zupts_`` and ``zupts_``; ``pseudo-std``, ``magnitude`` and ``shoe``
also ``fit(recordings, reference)`` their threshold on labelled zero-velocity
samples.

>>> from gaitml.zupt import detect_zupts
>>> det = detect_zupts(recording, detector="pseudo-std")   # doctest: +SKIP
>>> det.zupts_[["t_start_s", "t_end_s"]]                    # doctest: +SKIP
"""

from __future__ import annotations

import warnings

from gaitml.errors import InputError
from gaitml.zupt._base import BaseZuptDetector, reference_zupt_mask
from gaitml.zupt._intervals import (
    intervals_table,
    intervals_to_mask,
    local_stride_period,
    mask_runs,
    merge_short_gaps,
    remove_short_runs,
    stride_scaled_stances,
)
from gaitml.zupt.gyro_range import GyroRangeZuptDetector, gyro_range_zupts
from gaitml.zupt.magnitude import MagnitudeZuptDetector, magnitude_zupts
from gaitml.zupt.magnitude_std import MagnitudeStdZuptDetector, magnitude_std_zupts
from gaitml.zupt.pseudo_std import PAPER_THRESHOLD_RADS, PseudoStdZuptDetector, clean_stances, np_threshold, pseudo_std, pseudo_std_tangent
from gaitml.zupt.segment import label_strides, segment_strides
from gaitml.zupt.shoe import ShoeZuptDetector, shoe_statistic

__all__ = [
    "DETECTORS",
    "PAPER_THRESHOLD_RADS",
    "BaseZuptDetector",
    "DEPRECATED_NAMES",
    "GyroRangeZuptDetector",
    "MagnitudeStdZuptDetector",
    "MagnitudeZuptDetector",
    "PseudoStdZuptDetector",
    "ShoeZuptDetector",
    "clean_stances",
    "detect_zupts",
    "get_detector",
    "intervals_table",
    "intervals_to_mask",
    "label_strides",
    "local_stride_period",
    "gyro_range_zupts",
    "magnitude_std_zupts",
    "magnitude_zupts",
    "mask_runs",
    "merge_short_gaps",
    "np_threshold",
    "pseudo_std",
    "pseudo_std_tangent",
    "reference_zupt_mask",
    "remove_short_runs",
    "segment_strides",
    "shoe_statistic",
    "stride_scaled_stances",
]

#: name -> detector class (the names of DESIGN sec. 5 and ``gaitml zupt --detector``)
DETECTORS: dict[str, type[BaseZuptDetector]] = {
    "pseudo-std": PseudoStdZuptDetector,
    "magnitude": MagnitudeZuptDetector,
    "gyro-range": GyroRangeZuptDetector,
    "magnitude-std": MagnitudeStdZuptDetector,
    "shoe": ShoeZuptDetector,
}

#: old name -> registry name; accepted by :func:`get_detector` with a DeprecationWarning, not listed in DETECTORS
DEPRECATED_NAMES = {"method1": "gyro-range", "method2": "magnitude-std"}


def get_detector(name: str, **params) -> BaseZuptDetector:
    """A detector instance by registry name; unknown names or parameters raise InputError."""
    if name in DEPRECATED_NAMES:
        warnings.warn(
            f"the zero-velocity detector name {name!r} is deprecated; use {DEPRECATED_NAMES[name]!r}.", DeprecationWarning, stacklevel=2
        )
        name = DEPRECATED_NAMES[name]
    try:
        cls = DETECTORS[name]
    except KeyError:
        raise InputError(f"unknown zero-velocity detector {name!r}; choose one of {', '.join(DETECTORS)}.") from None
    try:
        return cls(**params)
    except TypeError as exc:
        raise InputError(f"bad parameters for zero-velocity detector {name!r}: {exc}; see help(gaitml.zupt.{cls.__name__}).") from None


def detect_zupts(recording, detector: str = "pseudo-std", **params) -> BaseZuptDetector:
    """Run a detector by name on a recording and return the fitted detector (``zupts_`` etc.)."""
    return get_detector(detector, **params).detect(recording)
