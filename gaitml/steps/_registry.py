"""Registry of step detectors by their CLI name (DESIGN sec. 5)."""

from __future__ import annotations

import importlib

import pandas as pd

from gaitml.errors import InputError, NotAvailableError
from gaitml.recording import Recording

__all__ = ["DETECTORS", "get_detector", "detect_steps", "detector_names"]

#: CLI name -> (module, class name); imported on first use.
_SPECS = {
    "single-peak": ("gaitml.steps.single_peak", "SinglePeakStepDetector"),
    "ifsm": ("gaitml.steps.ifsm", "IFSMStepDetector"),
    "ifsm-literal": ("gaitml.steps.ifsm", "IFSMLiteralStepDetector"),
    "adfsm": ("gaitml.steps.adfsm", "ADFSMStepDetector"),
    "autocorr": ("gaitml.steps.autocorr", "AutocorrStepDetector"),
    "fsm-selflearn": ("gaitml.steps.fsm_selflearn", "SelfLearningFSMStepDetector"),
    "adaptive": ("gaitml.steps.adaptive", "AdaptiveStepDetector"),
    "zupt-magnitude": ("gaitml.steps.zupt_magnitude", "ZuptMagnitudeStepDetector"),
}
#: detectors written elsewhere: imported lazily, a clear error when missing
_LAZY = ("zupt-magnitude",)


def detector_names() -> tuple[str, ...]:
    """All registered step detector names."""
    return tuple(_SPECS)


def _load(name: str) -> type:
    module, cls = _SPECS[name]
    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name == module:
            raise NotAvailableError(
                f"the step detector {name!r} is not available in this checkout ({module} is missing); choose another --detector."
            ) from exc
        raise
    try:
        return getattr(mod, cls)
    except AttributeError as exc:
        raise NotAvailableError(f"the step detector {name!r} is not available: {module} has no {cls}; choose another --detector.") from exc


class _Detectors(dict):
    """``{name: class}`` for the built-in detectors (``zupt-magnitude`` resolves lazily)."""

    def __missing__(self, key):
        if key in _LAZY:
            return _load(key)
        raise KeyError(key)

    def __contains__(self, key):
        return dict.__contains__(self, key) or key in _LAZY


DETECTORS = _Detectors({name: _load(name) for name in _SPECS if name not in _LAZY})


def get_detector(name: str, **params):
    """Instantiate the step detector registered as ``name`` with ``params``.

    Raises
    ------
    InputError
        For an unknown name (the message lists the valid ones) or bad parameters.
    NotAvailableError
        If ``zupt-magnitude`` is requested but its module is not in this checkout.
    """
    if name not in _SPECS:
        raise InputError(f"unknown step detector {name!r}; valid names: {', '.join(_SPECS)}.")
    cls = DETECTORS[name]
    try:
        return cls(**params)
    except TypeError as exc:
        raise InputError(f"bad parameters for step detector {name!r}: {exc}; see help(gaitml.steps.{cls.__name__}).") from exc


def detect_steps(recording: Recording, detector: str = "single-peak", **params) -> pd.DataFrame:
    """Detect steps in ``recording`` with the named detector; returns its step table."""
    return get_detector(detector, **params).detect(recording).steps_
