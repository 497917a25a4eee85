"""The family base of the step detectors: ``detect(recording) -> self`` sets ``steps_``.

A detector whose settings may be chosen on data declares them in ``param_grid``
(parameter -> candidate values); :meth:`BaseStepDetector.tune` picks the grid
point with the best mean count accuracy on the recordings it is given. The
evaluation (:mod:`gaitml.pipeline.steps_real`) calls it on the training users
(or positions) only and scores the choice on the held-out ones. A detector with
an empty grid (the paper detectors) is scored as it is.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Sequence
from typing import ClassVar

import numpy as np
import pandas as pd
from sklearn.base import clone

from gaitml._base import BaseAlgorithm
from gaitml.errors import InputError
from gaitml.recording import Recording, recorded_rate_hz
from gaitml.steps._rate import rate_check

__all__ = ["BaseStepDetector", "count_accuracy"]


def count_accuracy(n_detected: float, n_true: float) -> float:
    """``1 - |n_detected - n_true| / n_true`` (may be negative for a gross over-count)."""
    if not n_true or n_true <= 0:
        raise InputError(f"a count accuracy needs a positive true step count, got {n_true!r}; give the reference count.")
    return 1.0 - abs(float(n_detected) - float(n_true)) / float(n_true)


def _with_rate_check(detect):
    """``detect`` that then sets ``steps_.attrs['rate_check']`` (:func:`gaitml.steps.rate_check`): the recording's
    rate (:func:`gaitml.recording.recorded_rate_hz`, the rate before any up-sampling) against the detector's
    ``rate_floor_hz``. Nothing is printed and no step changes."""

    @functools.wraps(detect)
    def checked(self, recording, *args, **kwargs):
        out = detect(self, recording, *args, **kwargs)
        steps = getattr(self, "steps_", None)
        if isinstance(steps, pd.DataFrame) and isinstance(recording, Recording):
            meta = recording.meta
            steps.attrs["rate_check"] = rate_check(
                self.name or type(self).__name__,
                self.rate_floor_hz,
                recorded_rate_hz(recording.sampling_rate_hz, meta),
                (meta or {}).get("rate_changes"),
            )
        return out

    return checked


class BaseStepDetector(BaseAlgorithm):
    """Base of every step detector: one result, the DESIGN step table in ``steps_``.

    Every subclass's ``detect`` also leaves the rate check in ``steps_.attrs['rate_check']``
    (:mod:`gaitml.steps._rate`): whether the recording was made below ``rate_floor_hz``, the lowest rate at which
    the detector's count was measured to hold.
    """

    _action_method: ClassVar[str] = "detect"
    #: registry name (DESIGN sec. 5)
    name: ClassVar[str] = ""
    #: settings an evaluation may choose on training data: parameter -> candidate values (empty: none)
    param_grid: ClassVar[dict[str, tuple]] = {}
    #: the lowest recording rate (Hz) the detector's count holds at (its module's ``RATE_FLOOR_HZ``); None: not checked
    rate_floor_hz: ClassVar[float | None] = None
    steps_: pd.DataFrame

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "detect" in cls.__dict__:
            cls.detect = _with_rate_check(cls.__dict__["detect"])

    def detect(self, recording):  # pragma: no cover - abstract
        """Detect steps in ``recording``; sets ``steps_`` and returns ``self``."""
        raise NotImplementedError

    @classmethod
    def grid_points(cls) -> list[dict]:
        """Every combination of ``param_grid`` (``[]`` for a detector without one), in a fixed order."""
        if not cls.param_grid:
            return []
        names = sorted(cls.param_grid)
        return [dict(zip(names, values, strict=True)) for values in itertools.product(*(cls.param_grid[n] for n in names))]

    def tune(
        self,
        recordings: Sequence,
        n_true: Sequence[float],
        *,
        count: Callable[[dict, object], int] | None = None,
    ) -> dict:
        """Choose the ``param_grid`` setting with the best mean count accuracy on ``recordings``.

        Parameters
        ----------
        recordings : sequence of Recording
            The training recordings (never the ones the choice is scored on).
        n_true : sequence of float
            Their true step counts.
        count : callable ``(params, recording) -> int``, optional
            Step count of this detector with ``params`` set on ``recording``;
            default: clone, ``set_params(**params)``, ``detect``. An evaluation
            passes a cached one so that several folds share the detections.

        Returns
        -------
        dict
            The chosen parameters (``{}`` without a grid or without
            recordings). Ties go to the first grid point in :meth:`grid_points`
            order. ``self`` is not modified (set the result with
            ``set_params``).
        """
        grid = self.grid_points()
        if not grid or not len(recordings):
            return {}
        if len(recordings) != len(n_true):
            raise InputError(f"tune got {len(recordings)} recordings but {len(n_true)} true counts; give one count per recording.")
        if count is None:

            def count(params, rec):
                return len(clone(self).set_params(**params).detect(rec).steps_)

        best, best_score = grid[0], -np.inf
        for params in grid:
            score = float(np.mean([count_accuracy(count(params, rec), nt) for rec, nt in zip(recordings, n_true, strict=True)]))
            if score > best_score + 1e-12:
                best, best_score = params, score
        return dict(best)
