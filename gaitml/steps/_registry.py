"""Registry of step detectors by their CLI name (DESIGN sec. 5)."""

from __future__ import annotations

import pandas as pd

from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.steps._base import BaseStepDetector
from gaitml.steps.adaptive import AdaptiveStepDetector
from gaitml.steps.adfsm import ADFSMStepDetector
from gaitml.steps.autocorr import AutocorrStepDetector
from gaitml.steps.fsm_selflearn import SelfLearningFSMStepDetector
from gaitml.steps.ifsm import IFSMLiteralStepDetector, IFSMStepDetector
from gaitml.steps.single_peak import SinglePeakStepDetector
from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector

__all__ = ["DETECTORS", "get_detector", "detect_steps", "detector_names"]

#: CLI name -> step detector class
DETECTORS: dict[str, type[BaseStepDetector]] = {
    "single-peak": SinglePeakStepDetector,
    "ifsm": IFSMStepDetector,
    "ifsm-literal": IFSMLiteralStepDetector,
    "adfsm": ADFSMStepDetector,
    "autocorr": AutocorrStepDetector,
    "fsm-selflearn": SelfLearningFSMStepDetector,
    "adaptive": AdaptiveStepDetector,
    "zupt-magnitude": ZuptMagnitudeStepDetector,
}


def detector_names() -> tuple[str, ...]:
    """All registered step detector names."""
    return tuple(DETECTORS)


def get_detector(name: str, **params) -> BaseStepDetector:
    """Instantiate the step detector registered as ``name`` with ``params``.

    Raises
    ------
    InputError
        For an unknown name (the message lists the valid ones) or unknown parameters.
    """
    if name not in DETECTORS:
        raise InputError(f"unknown step detector {name!r}; valid names: {', '.join(DETECTORS)}.")
    cls = DETECTORS[name]
    try:
        return cls(**params)
    except TypeError as exc:
        raise InputError(f"bad parameters for step detector {name!r}: {exc}; see help(gaitml.steps.{cls.__name__}).") from exc


def detect_steps(recording: Recording, detector: str = "single-peak", **params) -> pd.DataFrame:
    """Detect steps in ``recording`` with the named detector; returns its step table."""
    return get_detector(detector, **params).detect(recording).steps_
