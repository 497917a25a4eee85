"""Step detectors (one algorithm per module), their registry and the step table.

``DETECTORS`` maps the CLI names of DESIGN sec. 5 to classes; every class takes
its parameters in ``__init__`` and has ``detect(recording) -> self`` leaving the
DESIGN step table in ``steps_``. Each class declares ``rate_floor_hz``, the lowest
recording rate its count holds at; ``steps_.attrs['rate_check']`` says whether the
recording was made below it (:mod:`gaitml.steps._rate`, :func:`rate_floors`).
"""

from gaitml.steps._base import BaseStepDetector
from gaitml.steps._rate import RATE_TOLERANCE, add_rate_reasons, rate_check, rate_flags, rate_reason, rate_record, rate_warning
from gaitml.steps._registry import DETECTORS, detect_steps, detector_names, get_detector, rate_floors
from gaitml.steps._table import empty_step_table, make_step_table
from gaitml.steps._unsure import CONFIDENT_BOUT_STEPS, CONFIDENT_WINDOW_S, confident_steps, gait_confidence
from gaitml.steps.adaptive import AdaptiveStepDetector
from gaitml.steps.adfsm import ADFSMStepDetector
from gaitml.steps.autocorr import AutocorrStepDetector
from gaitml.steps.fsm_selflearn import SelfLearningFSMStepDetector
from gaitml.steps.ifsm import IFSMLiteralStepDetector, IFSMStepDetector
from gaitml.steps.single_peak import SinglePeakStepDetector
from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector

__all__ = [
    "CONFIDENT_BOUT_STEPS",
    "CONFIDENT_WINDOW_S",
    "DETECTORS",
    "RATE_TOLERANCE",
    "ADFSMStepDetector",
    "AdaptiveStepDetector",
    "AutocorrStepDetector",
    "BaseStepDetector",
    "IFSMLiteralStepDetector",
    "IFSMStepDetector",
    "SelfLearningFSMStepDetector",
    "SinglePeakStepDetector",
    "ZuptMagnitudeStepDetector",
    "confident_steps",
    "detect_steps",
    "detector_names",
    "empty_step_table",
    "gait_confidence",
    "get_detector",
    "make_step_table",
    "rate_check",
    "rate_flags",
    "rate_floors",
    "rate_reason",
    "add_rate_reasons",
    "rate_record",
    "rate_warning",
]
