"""The family base of the step detectors: ``detect(recording) -> self`` sets ``steps_``."""

from __future__ import annotations

from typing import ClassVar

import pandas as pd

from gaitml._base import BaseAlgorithm

__all__ = ["BaseStepDetector"]


class BaseStepDetector(BaseAlgorithm):
    """Base of every step detector: one result, the DESIGN step table in ``steps_``."""

    _action_method: ClassVar[str] = "detect"
    #: registry name (DESIGN sec. 5)
    name: ClassVar[str] = ""
    steps_: pd.DataFrame

    def detect(self, recording):  # pragma: no cover - abstract
        """Detect steps in ``recording``; sets ``steps_`` and returns ``self``."""
        raise NotImplementedError
