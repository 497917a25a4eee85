"""Registry of step detectors by their CLI name (DESIGN sec. 5)."""

from __future__ import annotations

from gaitml._base import Registry
from gaitml.recording import Recording
from gaitml.steps._base import BaseStepDetector
from gaitml.steps.adaptive import AdaptiveStepDetector
from gaitml.steps.adfsm import ADFSMStepDetector
from gaitml.steps.autocorr import AutocorrStepDetector
from gaitml.steps.fsm_selflearn import SelfLearningFSMStepDetector
from gaitml.steps.ifsm import IFSMLiteralStepDetector, IFSMStepDetector
from gaitml.steps.single_peak import SinglePeakStepDetector
from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector

__all__ = ["DETECTORS", "get_detector", "detect_steps", "detector_names", "rate_floors"]

#: CLI name -> step detector class
DETECTORS: Registry = Registry(
    "step detector",
    {
        "single-peak": SinglePeakStepDetector,
        "ifsm": IFSMStepDetector,
        "ifsm-literal": IFSMLiteralStepDetector,
        "adfsm": ADFSMStepDetector,
        "autocorr": AutocorrStepDetector,
        "fsm-selflearn": SelfLearningFSMStepDetector,
        "adaptive": AdaptiveStepDetector,
        "zupt-magnitude": ZuptMagnitudeStepDetector,
    },
    module="gaitml.steps",
)


def detector_names() -> tuple[str, ...]:
    """All registered step detector names."""
    return DETECTORS.names()


def rate_floors() -> dict[str, float | None]:
    """Each registered detector's rate floor (Hz): the lowest recording rate its count holds at
    (``rate_floor_hz``; :mod:`gaitml.steps._rate`)."""
    return {name: DETECTORS[name].rate_floor_hz for name in DETECTORS.names()}


def get_detector(name: str, **params) -> BaseStepDetector:
    """Instantiate the step detector registered as ``name`` with ``params`` (:meth:`gaitml._base.Registry.create`).

    Raises
    ------
    InputError
        For an unknown name (the message lists the valid ones) or unknown parameters.
    """
    return DETECTORS.create(name, **params)


def detect_steps(recording: Recording, detector: str = "single-peak", *, return_detector: bool = False, **params):
    """Detect steps in ``recording`` with the named detector.

    Returns its step table (``steps_``), or with ``return_detector=True`` the fitted
    detector (as :func:`gaitml.zupt.detect_zupts`).
    """
    det = get_detector(detector, **params).detect(recording)
    return det if return_detector else det.steps_
