"""Zero-velocity (ZUPT) detectors, one algorithm per module, behind one API.

Detectors (DESIGN sec. 4/5 names): ``pseudo-std`` (paper 001), ``magnitude``
(paper 004), ``method1`` and ``method2`` (paper 001's baselines) and ``shoe``
(Skog et al. 2010). Each has ``detect(recording) -> self`` setting
``per_sample_zupts_`` and ``zupts_``; ``pseudo-std``, ``magnitude`` and ``shoe``
also ``fit(recordings, reference)`` their threshold on labelled zero-velocity
samples.

>>> from gaitml.zupt import detect_zupts
>>> det = detect_zupts(recording, detector="pseudo-std")   # doctest: +SKIP
>>> det.zupts_[["t_start_s", "t_end_s"]]                    # doctest: +SKIP
"""

from __future__ import annotations

from gaitml.errors import InputError
from gaitml.zupt._base import BaseZuptDetector, reference_zupt_mask
from gaitml.zupt._intervals import intervals_table, intervals_to_mask, mask_runs, remove_short_runs
from gaitml.zupt.magnitude import MagnitudeZuptDetector, magnitude_zupts
from gaitml.zupt.method1 import Method1ZuptDetector, method1_zupts
from gaitml.zupt.method2 import Method2ZuptDetector, method2_zupts
from gaitml.zupt.pseudo_std import PAPER_THRESHOLD_RADS, PseudoStdZuptDetector, np_threshold, pseudo_std, pseudo_std_tangent
from gaitml.zupt.segment import label_strides, segment_strides
from gaitml.zupt.shoe import ShoeZuptDetector, shoe_statistic

__all__ = [
    "DETECTORS",
    "PAPER_THRESHOLD_RADS",
    "BaseZuptDetector",
    "MagnitudeZuptDetector",
    "Method1ZuptDetector",
    "Method2ZuptDetector",
    "PseudoStdZuptDetector",
    "ShoeZuptDetector",
    "detect_zupts",
    "get_detector",
    "intervals_table",
    "intervals_to_mask",
    "label_strides",
    "magnitude_zupts",
    "mask_runs",
    "method1_zupts",
    "method2_zupts",
    "np_threshold",
    "pseudo_std",
    "pseudo_std_tangent",
    "reference_zupt_mask",
    "remove_short_runs",
    "segment_strides",
    "shoe_statistic",
]

#: name -> detector class (the names of DESIGN sec. 5 and ``gaitml zupt --detector``)
DETECTORS: dict[str, type[BaseZuptDetector]] = {
    "pseudo-std": PseudoStdZuptDetector,
    "magnitude": MagnitudeZuptDetector,
    "method1": Method1ZuptDetector,
    "method2": Method2ZuptDetector,
    "shoe": ShoeZuptDetector,
}


def get_detector(name: str, **params) -> BaseZuptDetector:
    """A detector instance by registry name; unknown names or parameters raise InputError."""
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
