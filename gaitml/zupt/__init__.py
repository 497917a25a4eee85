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
>>> zupts = detect_zupts(recording, detector="pseudo-std")   # doctest: +SKIP
>>> zupts[["t_start_s", "t_end_s"]]                           # doctest: +SKIP
"""

from __future__ import annotations

from gaitml._base import Registry
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
    "detector_names",
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

#: name -> detector class (the names of DESIGN sec. 5 and ``gaitml zupt --detector``); old names
#: (``DEPRECATED_NAMES``) are accepted by :func:`get_detector` with a DeprecationWarning, not listed
DETECTORS: Registry = Registry(
    "zero-velocity detector",
    {
        "pseudo-std": PseudoStdZuptDetector,
        "magnitude": MagnitudeZuptDetector,
        "gyro-range": GyroRangeZuptDetector,
        "magnitude-std": MagnitudeStdZuptDetector,
        "shoe": ShoeZuptDetector,
    },
    module="gaitml.zupt",
    deprecated={"method1": "gyro-range", "method2": "magnitude-std"},
)
#: old name -> registry name
DEPRECATED_NAMES = DETECTORS.deprecated


def detector_names() -> tuple[str, ...]:
    """All registered zero-velocity detector names."""
    return DETECTORS.names()


def get_detector(name: str, **params) -> BaseZuptDetector:
    """A detector instance by registry name (:meth:`gaitml._base.Registry.create`); unknown names or parameters raise InputError."""
    return DETECTORS.create(name, **params)


def detect_zupts(recording, detector: str = "pseudo-std", *, return_detector: bool = False, **params):
    """Detect zero-velocity intervals in ``recording`` with the named detector.

    Returns its interval table (``zupts_``), or with ``return_detector=True`` the fitted
    detector (``per_sample_zupts_`` etc.; what this function returned before), as
    :func:`gaitml.steps.detect_steps`.
    """
    det = get_detector(detector, **params).detect(recording)
    return det if return_detector else det.zupts_
