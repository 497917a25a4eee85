"""Gait segmentation as one API: steps, strides or zero-velocity intervals as a table of segments.

:func:`segment` cuts a recording into segments with one of three front ends:

- ``by='steps'``: a step detector (:data:`gaitml.steps.DETECTORS`, default
  :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`); one segment per detected step, ``[start, end)`` of the step
  table (the detector's own step segmentation, e.g. zero crossings or troughs
  around the peak; paper 002 sec. 2 for ``fsm-selflearn``).
- ``by='strides'``: a zero-velocity detector (:data:`gaitml.zupt.DETECTORS`,
  default ``pseudo-std``) and :func:`gaitml.zupt.segment_strides`; one segment per
  stride, from mid-stance to mid-stance (foot-mounted sensors).
- ``by='zupt'``: the same detectors; one segment per zero-velocity interval (the
  stance phases themselves).

Every table has the columns of :data:`SEGMENT_COLUMNS`: ``index`` (0, 1, ...),
``kind`` (step, stride or stance), ``start``, ``end`` (samples, ``end``
exclusive), ``start_s``, ``end_s``, ``duration_s`` and ``confidence`` (the
detector's per-segment confidence in [0, 1] where its table has a
``confidence`` column, e.g. ``adaptive``'s steps; NaN otherwise), followed by
a few columns of the front end: ``event_s`` (the step's time, ``attrs['event']``
of the step table) for steps; ``stance_end_s`` and ``swing_end_s`` for strides.
``attrs`` carry ``by``, ``detector`` and ``sampling_rate_hz``, and for steps from a detector
that tests gait evidence (``adaptive``, :mod:`gaitml.steps._gait_evidence`) ``gait_check``: how
many steps it left out in bouts without gait evidence. Steps also carry ``rate_check`` in ``attrs``
(:func:`gaitml.steps.rate_record`: was the recording made below the lowest rate the detector's count holds
at?) and, when a step was, a ``rate_reason`` column (:func:`gaitml.steps.rate_flags`).

>>> from gaitml.segment import segment
>>> segment(recording, by="strides", detector="pseudo-std")   # doctest: +SKIP
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.steps._rate import add_rate_reasons, rate_record
from gaitml.steps._table import gait_check_record

__all__ = ["BY", "SEGMENT_COLUMNS", "DEFAULT_DETECTORS", "segment", "resolve_detector"]

#: The front ends of :func:`segment`.
BY = ("steps", "strides", "zupt")
#: Default detector of each front end.
DEFAULT_DETECTORS = {"steps": DEFAULT_STEP_DETECTOR, "strides": "pseudo-std", "zupt": "pseudo-std"}
#: Columns every segment table starts with.
SEGMENT_COLUMNS = ("index", "kind", "start", "end", "start_s", "end_s", "duration_s", "confidence")
_KIND = {"steps": "step", "strides": "stride", "zupt": "stance"}


def _registries():
    from gaitml.steps import DETECTORS as STEP_DETECTORS
    from gaitml.steps import BaseStepDetector
    from gaitml.zupt import DETECTORS as ZUPT_DETECTORS
    from gaitml.zupt import BaseZuptDetector

    return (STEP_DETECTORS, BaseStepDetector), (ZUPT_DETECTORS, BaseZuptDetector)


def resolve_detector(by: str, detector=None):
    """The detector instance for ``by`` from a registry name, an instance, or None (the default).

    Raises
    ------
    InputError
        For an unknown ``by``, a name from the wrong registry or an unknown name
        (the message lists the valid names), or an object of the wrong kind.
    """
    if by not in BY:
        raise InputError(f"unknown segmentation {by!r}; choose by one of {', '.join(BY)}.")
    (steps_reg, step_base), (zupt_reg, zupt_base) = _registries()
    reg, base, what = (steps_reg, step_base, "step") if by == "steps" else (zupt_reg, zupt_base, "zero-velocity")
    if detector is None:
        detector = DEFAULT_DETECTORS[by]
    if isinstance(detector, str):
        if detector not in reg:
            other = "zero-velocity" if by == "steps" else "step"
            known_elsewhere = detector in (zupt_reg if by == "steps" else steps_reg)
            hint = f" ({detector!r} is a {other} detector)" if known_elsewhere else ""
            raise InputError(f"unknown {what} detector {detector!r} for --by {by}{hint}; choose one of {', '.join(reg)}.")
        return reg[detector]()
    if not isinstance(detector, base):
        raise InputError(
            f"by={by!r} needs a {what} detector (a {base.__name__} or one of {', '.join(reg)}), got {type(detector).__name__}; "
            "pass a registry name or a detector object of that kind."
        )
    return detector


def _confidence(table: pd.DataFrame) -> np.ndarray:
    if "confidence" in table.columns:
        return np.asarray(table["confidence"], dtype=float)
    return np.full(len(table), np.nan)


def _frame(by: str, start, end, fs: float, confidence: np.ndarray, extra: dict) -> pd.DataFrame:
    start = np.asarray(start, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    out = pd.DataFrame(
        {
            "index": np.arange(len(start), dtype=np.int64),
            "kind": np.full(len(start), _KIND[by], dtype=object),
            "start": start,
            "end": end,
            "start_s": start / fs,
            "end_s": end / fs,
            "duration_s": (end - start) / fs,
            "confidence": np.asarray(confidence, dtype=float),
            **extra,
        }
    )
    return out


def segment(recording: Recording, by: str = "steps", detector=None, *, max_stride_s: float | None = None) -> pd.DataFrame:
    """Cut a recording into steps, strides or zero-velocity intervals.

    Parameters
    ----------
    recording : Recording
    by : {'steps', 'strides', 'zupt'}
        The front end (see the module doc).
    detector : str or detector object, optional
        A registry name (step detectors for ``steps``; zero-velocity detectors for
        ``strides`` and ``zupt``) or a configured detector instance of that kind.
        Default: :data:`gaitml.consts.DEFAULT_STEP_DETECTOR` (steps), ``pseudo-std`` (strides, zupt).
    max_stride_s : float, optional
        ``by='strides'`` only: drop strides longer than this (s), e.g. across a pause.

    Returns
    -------
    DataFrame
        One row per segment, the columns of :data:`SEGMENT_COLUMNS` first (see the
        module doc); times in s, ``start``/``end`` in samples (``end`` exclusive).

    Raises
    ------
    InputError
        Bad ``by`` or detector (the message names the valid ones), a recording a
        detector cannot use (e.g. no gyroscope for a zero-velocity detector).
    """
    if not isinstance(recording, Recording):
        raise InputError(f"segment needs a gaitml Recording, got {type(recording).__name__}; read files with gaitml.io.read_recording.")
    det = resolve_detector(by, detector)
    if max_stride_s is not None and by != "strides":
        raise InputError(f"max_stride_s applies to by='strides' only, not {by!r}; drop it.")
    fs = float(recording.sampling_rate_hz)
    name = getattr(det, "name", "") or type(det).__name__
    if by == "steps":
        steps = det.detect(recording).steps_
        event = steps.attrs.get("event", "t_peak_s")
        ev = steps[event] if event in steps.columns else steps["t_peak_s"]
        out = _frame(by, steps["start"], steps["end"], fs, _confidence(steps), {"event_s": np.asarray(ev, dtype=float)})
    else:
        from gaitml.zupt import segment_strides

        zupts = det.detect(recording).zupts_
        if by == "zupt":
            out = _frame(by, zupts["start"], zupts["end"], fs, _confidence(zupts), {})
        else:
            if max_stride_s is not None and not (np.isfinite(max_stride_s) and max_stride_s > 0):
                raise InputError(f"max_stride_s must be a positive number of seconds, got {max_stride_s!r}.")
            st = segment_strides(zupts, fs, max_stride_s=max_stride_s)
            out = _frame(
                by,
                st["start"],
                st["end"],
                fs,
                _confidence(st),
                {"stance_end_s": st["stance_end"].to_numpy() / fs, "swing_end_s": st["swing_end"].to_numpy() / fs},
            )
    out.attrs.update({"by": by, "detector": name, "sampling_rate_hz": fs})
    if by == "steps" and steps.attrs.get("gait_check") is not None:  # steps left out in bouts without gait evidence
        out.attrs["gait_check"] = gait_check_record(steps.attrs["gait_check"])
    if by == "steps" and steps.attrs.get("rate_check") is not None:  # recorded below the detector's rate floor
        out.attrs["rate_check"] = rate_record(steps)
        add_rate_reasons(out, steps)
    return out
