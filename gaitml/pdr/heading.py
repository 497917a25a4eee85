"""The family base of the heading sources and the raw gyro heading.

A heading source gives one facing heading per step: ``estimate(recording, steps)``
sets ``heading_rad_`` (shape (n_steps,), rad, compass) and returns ``self``. All
of them start from the gyro attitude (:class:`~gaitml.pdr.attitude.AttitudeEstimator`,
a nested parameter so ``sklearn.base.clone`` copies it), averaged over each step
window (``gyro_heading_rad_``).

The ``steps`` table is the DESIGN step table (``start``, ``end`` and the event time
column named by ``steps.attrs['event']``), optionally with:

- ``mode``: the motion mode per step (DW-PCA: concavity polarity and mode offset);
- ``mode_offset_rad``: the offset between facing and motion direction per step
  (default: :func:`~gaitml.pdr.update.mode_offsets_rad` of ``mode``, 0 without modes);
- ``window_start`` / ``window_end``: the PCA window per step (default ``start`` /
  ``end``; the self-learning FSM's S2..S6 segments, paper 002 sec. 3.1).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd
from sklearn.base import clone

from gaitml._base import BaseAlgorithm
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, step_headings
from gaitml.recording import Recording

__all__ = ["BaseHeadingSource", "GyroHeading"]


class BaseHeadingSource(BaseAlgorithm):
    """Base of the heading sources: ``estimate(recording, steps) -> self`` sets ``heading_rad_`` per step."""

    _action_method: ClassVar[str] = "estimate"
    name: ClassVar[str] = ""
    #: whether the heading needs only per-step inputs (the gyro step headings, step times and
    #: durations), so that :meth:`estimate_steps` can run it on a long recording whose attitude
    #: was integrated chunk by chunk (:func:`gaitml.chunked_run.long_pdr`)
    steps_only: ClassVar[bool] = False

    def _attitude(self, recording: Recording) -> AttitudeEstimator:
        att = AttitudeEstimator() if self.attitude is None else clone(self.attitude)
        if not isinstance(att, AttitudeEstimator):
            raise InputError(f"`attitude` must be an AttitudeEstimator or None, got {type(self.attitude).__name__}.")
        return att.estimate(recording)

    def _heading(self, recording: Recording, steps: pd.DataFrame, gyro_h: np.ndarray, t_step: np.ndarray, dur: np.ndarray) -> np.ndarray:
        raise NotImplementedError  # pragma: no cover - abstract

    def estimate(self, recording: Recording, steps: pd.DataFrame):
        """Heading per step of ``steps`` in ``recording``; sets ``heading_rad_`` and returns ``self``.

        Also sets ``attitude_`` (the fitted attitude estimator) and
        ``gyro_heading_rad_`` (mean gyro heading over each step window).
        """
        self._validate_params()
        if not isinstance(recording, Recording):
            raise InputError(f"`recording` must be a gaitml Recording, got {type(recording).__name__}.")
        if not isinstance(steps, pd.DataFrame) or not {"start", "end"} <= set(steps.columns):
            raise InputError("`steps` must be a step table with `start` and `end` columns; run a step detector first.")
        recording.require_gyr("PDR heading")
        n = len(steps)
        start = steps["start"].to_numpy(np.int64)
        end = np.maximum(steps["end"].to_numpy(np.int64), start + 1)
        event = steps.attrs.get("event", "t_peak_s")
        t_step = steps[event if event in steps else "t_peak_s"].to_numpy(float) if n else np.zeros(0)
        dur = np.maximum(end - start, 1) / recording.sampling_rate_hz
        self.attitude_ = self._attitude(recording)
        self.gyro_heading_rad_ = step_headings(self.attitude_.heading_rad_, start, end) if n else np.zeros(0)
        self.heading_rad_ = self._heading(recording, steps, self.gyro_heading_rad_, t_step, dur) if n else np.zeros(0)
        return self

    def estimate_steps(self, steps: pd.DataFrame, gyro_heading_rad, sampling_rate_hz: float):
        """:meth:`estimate` from the gyro step headings alone (sources with ``steps_only``).

        ``gyro_heading_rad`` is the mean attitude heading over each step window (what
        :meth:`estimate` computes as ``gyro_heading_rad_``), e.g. from an attitude integrated
        chunk by chunk; sets ``gyro_heading_rad_`` and ``heading_rad_`` and returns ``self``
        (no ``attitude_``: there is no single attitude run).
        """
        self._validate_params()
        if not self.steps_only:
            raise InputError(
                f"the {self.name or type(self).__name__} heading needs the recording's samples, not only step headings; use estimate()."
            )
        if not isinstance(steps, pd.DataFrame) or not {"start", "end"} <= set(steps.columns):
            raise InputError("`steps` must be a step table with `start` and `end` columns; run a step detector first.")
        n = len(steps)
        gyro_h = np.asarray(gyro_heading_rad, dtype=float).reshape(-1)
        if len(gyro_h) != n:
            raise InputError(f"`gyro_heading_rad` must have one value per step ({n}), got {len(gyro_h)}.")
        start = steps["start"].to_numpy(np.int64)
        end = np.maximum(steps["end"].to_numpy(np.int64), start + 1)
        event = steps.attrs.get("event", "t_peak_s")
        t_step = steps[event if event in steps else "t_peak_s"].to_numpy(float) if n else np.zeros(0)
        dur = np.maximum(end - start, 1) / float(sampling_rate_hz)
        self.gyro_heading_rad_ = gyro_h
        self.heading_rad_ = self._heading(None, steps, gyro_h, t_step, dur) if n else np.zeros(0)
        return self


class GyroHeading(BaseHeadingSource):
    """The raw gyro heading per step (no correction): the baseline heading source.

    Parameters
    ----------
    attitude : AttitudeEstimator, optional
        The attitude estimator whose heading is averaged over each step (default
        ``AttitudeEstimator()``).

    Attributes
    ----------
    heading_rad_ : (n_steps,) mean gyro heading over each step window (rad).
    gyro_heading_rad_ : the same values.
    attitude_ : the fitted attitude estimator.
    """

    name = "gyro"
    steps_only = True

    def __init__(self, *, attitude: AttitudeEstimator | None = None):
        self.attitude = attitude

    def _heading(self, recording, steps, gyro_h, t_step, dur):
        return gyro_h
