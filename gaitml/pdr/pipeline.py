"""The PDR pipeline: recording -> steps -> mode per step -> length -> heading -> positions.

Paper 003 sec. 4 (with paper 002 sec. 3 as an alternative heading source), DESIGN sec. 4-5.

- Steps: a registered step detector (:data:`gaitml.consts.DEFAULT_STEP_DETECTOR` by default;
  paper 003 sec. 2.2 uses ``single-peak``), or a
  step table given by the caller.
- Mode per step: from a saved model's window predictions (the window containing the step
  time; with overlapping windows the one whose centre is nearest; then every mode change
  is re-placed at the most likely step, :mod:`gaitml.pdr.step_modes`), from the recording's
  true per-sample labels (majority over the step window), or ``forward`` (no recognition:
  every step is a walk step and the traditional update is used, the baseline of paper
  003 sec. 4.3).
- Length: :class:`~gaitml.pdr.step_length.StepLengthModel` by mode.
- Heading: gyro attitude (:mod:`gaitml.pdr.attitude`) per step; corrected by buffered HDE
  (``hde``), or DW-PCA step direction (``dwpca``), or raw (``gyro``).
- Update: multi-state (paper 003 eq. 11, physical reading) or forward-only (eq. 10).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.base import clone

from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator, wrap_angle
from gaitml.pdr.dwpca import DwPcaHdeHeading, DwPcaHeading
from gaitml.pdr.hde import HeuristicDriftElimination
from gaitml.pdr.heading import BaseHeadingSource, GyroHeading
from gaitml.pdr.step_length import StepLengthModel, step_length_features
from gaitml.pdr.step_modes import (
    MODE_ASSIGNMENTS,
    SHORT_RUN_DEFAULT,
    forward_short_runs,
    modes_from_step_model,
    modes_from_windows,
    next_step_times,
    refine_mode_boundaries,
    window_values_at_steps,
)
from gaitml.pdr.update import forward_update, mode_offsets_rad, multi_state_update
from gaitml.recording import Recording
from gaitml.steps._rate import add_rate_reasons, rate_record
from gaitml.steps._table import gait_check_record

__all__ = ["HEADING_SOURCES", "MODE_SOURCES", "PdrResult", "modes_from_labels", "modes_from_windows", "run_pdr"]

#: name -> heading source class (``run_pdr(heading=...)``, ``gaitml pdr --heading``)
HEADING_SOURCES: dict[str, type[BaseHeadingSource]] = {
    "hde": HeuristicDriftElimination,
    "dwpca": DwPcaHeading,
    "gyro": GyroHeading,
    "dwpca-hde": DwPcaHdeHeading,
}
MODE_SOURCES = ("model", "true", "forward")
TRAJECTORY_COLUMNS = ("t_s", "x_m", "y_m", "heading_rad", "mode", "step_length_m")


@dataclass
class PdrResult:
    """Output of :func:`run_pdr`.

    Attributes
    ----------
    trajectory : DataFrame, one row per step preceded by the start point: ``t_s``, ``x_m``,
        ``y_m``, ``heading_rad`` (facing heading of the step; the start row has the
        initial heading), ``mode`` (``start`` for the first row), ``step_length_m`` (0 at
        the start); ``in_domain`` with model modes; ``rate_reason`` when a step was recorded below the step
        detector's rate floor (:func:`gaitml.steps.rate_flags`; ``""`` for a step that was not); and
        ``step_length_outside_fit`` with a calibrated step-length model that records its fitted inputs
        (:meth:`~gaitml.pdr.step_length.StepLengthModel.outside_fit`). The start row has None in these.
    steps : DataFrame, the step table with the per-step ``mode``, ``step_length_m``,
        ``heading_rad``, ``gyro_heading_rad`` and step-length features.
    distance_m : float, sum of the step lengths.
    end_xy_m : (x, y) of the last position.
    info : dict, how it was computed (detector, heading and mode sources, notes).
    """

    trajectory: pd.DataFrame
    steps: pd.DataFrame
    distance_m: float
    end_xy_m: tuple[float, float]
    info: dict = field(default_factory=dict)

    @property
    def n_steps(self) -> int:
        return len(self.steps)

    def to_json_dict(self) -> dict:
        """The ``gaitml pdr --json`` object (DESIGN sec. 5).

        With a model (``modes='model'``) every trajectory row also has ``in_domain``
        (None for the start row and for a model without a domain record) and
        ``out_of_domain_reason`` (why its step is out of domain; None for the start row, a step
        in domain and a model without a domain record, as ``gaitml predict --json``'s windows) and the object
        has ``out_of_domain_steps`` and ``side_direction_unsure_steps`` (side steps moved
        forward because the model cannot tell their direction; None for a model without a
        domain record), ``short_run_steps`` (side or backward steps moved forward by the short-run rule,
        ``run_pdr(short_run_windows=)``; None for a step-window model), and ``foot_mounted_steps`` (steps whose window rests between fast swings as a
        foot-mounted sensor does, :mod:`gaitml.models._placement`) when that rule ran (a model with a domain
        record and no foot in its training positions); without a model they are absent. ``gait_check``: the step detector's
        gait-evidence account (steps left out in bouts without gait evidence), when it ran. ``rate_check``: the step
        table's rate check (:func:`gaitml.steps.rate_record`: was the recording made below the lowest rate the step
        detector's count holds at?), null for a step table without one (steps given by the caller); when a step
        was, every trajectory row has ``rate_reason`` (null for the start row and a step that was not).
        ``step_length_outside_fit``: with a calibrated step-length model that records its fitted inputs, how many
        steps lie outside them (their lengths extrapolated; :meth:`~gaitml.pdr.step_length.StepLengthModel.outside_fit`),
        and per trajectory row whether its step does (null for the start row). ``step_length_detector``
        (``calibrated_with``, ``detector``): present when the calibration was fitted on another step detector's
        steps (:func:`calibration_detector_check`). ``heading_check``: with an HDE heading (``hde``, ``dwpca-hde``),
        its structure guard's record (:func:`gaitml.pdr.hde.hde_heading`: ``guard``, ``statistic``, ``threshold``,
        ``n_steps``, ``min_steps``, ``structured``, ``hde_applied``, ``reason``); absent for the other headings and
        when there are no steps (HDE did not run).
        """
        traj = self.trajectory
        rows = [
            {"t_s": float(t), "x_m": float(x), "y_m": float(y), "heading_rad": float(h), "mode": str(m)}
            for t, x, y, h, m in zip(traj["t_s"], traj["x_m"], traj["y_m"], traj["heading_rad"], traj["mode"], strict=True)
        ]
        if "in_domain" in traj:
            for row, v in zip(rows, traj["in_domain"], strict=True):
                row["in_domain"] = None if v is None else bool(v)
            if "out_of_domain_reason" in self.steps:
                for row, r in zip(rows[1:], self.steps["out_of_domain_reason"], strict=True):
                    row["out_of_domain_reason"] = str(r) if r else None
                rows[0]["out_of_domain_reason"] = None
        if "rate_reason" in traj:  # per step, when a step was recorded below the detector's rate floor
            for row, v in zip(rows, traj["rate_reason"], strict=True):
                row["rate_reason"] = None if pd.isna(v) else str(v) or None
        if "step_length_outside_fit" in traj:  # per step, with a calibration that records its fitted inputs
            for row, v in zip(rows, traj["step_length_outside_fit"], strict=True):
                row["step_length_outside_fit"] = None if pd.isna(v) else bool(v)
        out = {
            "n_steps": int(self.n_steps),
            "distance_m": float(self.distance_m),
            "end_xy_m": [float(self.end_xy_m[0]), float(self.end_xy_m[1])],
            "trajectory": rows,
        }
        if self.info.get("modes") == "model":
            out["out_of_domain_steps"] = self.info.get("out_of_domain_steps")
            out["side_direction_unsure_steps"] = self.info.get("side_direction_unsure_steps")
            out["short_run_steps"] = self.info.get("short_run_steps")
            if "foot_mounted_steps" in self.info:
                out["foot_mounted_steps"] = self.info["foot_mounted_steps"]
        if self.info.get("gyro_bias") is not None:
            out["gyro_bias"] = self.info["gyro_bias"]
        if self.info.get("heading_check") is not None:
            out["heading_check"] = self.info["heading_check"]
        if self.info.get("gait_check") is not None:
            out["gait_check"] = self.info["gait_check"]
        out["rate_check"] = self.info.get("rate_check")
        if self.info.get("step_length_outside_fit") is not None:
            out["step_length_outside_fit"] = int(self.info["step_length_outside_fit"])
        if self.info.get("step_length_detector") is not None:
            out["step_length_detector"] = self.info["step_length_detector"]
        return out


def modes_from_labels(labels: np.ndarray, start, end) -> np.ndarray:
    """Majority per-sample label over each step window ``[start, end)``."""
    lab = np.asarray(labels).astype(str)
    start = np.asarray(start, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    classes, codes = np.unique(lab, return_inverse=True)
    # per-class cumulative counts: majority per window without a Python loop over samples
    onehot = np.zeros((len(lab) + 1, len(classes)), dtype=np.int64)
    onehot[1 + np.arange(len(lab)), codes] = 1
    cum = np.cumsum(onehot, axis=0)
    counts = cum[end] - cum[start]
    return classes[np.argmax(counts, axis=1)]


def _out_of_domain_steps(model, windows: pd.DataFrame, t_look, step_modes) -> tuple:
    """Per-step in-domain flags; out-of-domain steps, and side steps of unsure direction, move along the facing heading.

    A side step whose window the model marks ``side_direction_unsure`` (a carrying position
    where the phone's placement flips the lateral axis, :mod:`gaitml.models`) also walks
    forward: its direction is a guess. A step takes the flag of the window nearest it (as its mode does). A step whose
    window lies outside the model's training domain (:mod:`gaitml.models.domain`) gets
    the mode ``walk`` (forward along the facing heading, the traditional PDR update)
    instead of the model's mode, which is unreliable there; the model's mode is kept in
    the step table's ``mode_model``. A model without a domain record leaves the modes
    unchanged and the flags None.

    Returns
    -------
    (in_domain, modes, model_modes) : object array of True/False/None, str arrays.
    """
    model_modes = np.asarray(step_modes).astype(str)
    n = len(model_modes)
    if n == 0 or "in_domain" not in windows:
        return np.full(n, None, dtype=object), model_modes, model_modes
    flags = window_values_at_steps(windows, t_look, "in_domain")
    flags = np.array([None if v is None else bool(v) for v in flags], dtype=object)
    if getattr(model, "domain", None) is None:
        return flags, model_modes, model_modes
    ood = np.array([v is False for v in flags])
    modes = np.where(ood, "walk", model_modes)
    if "side_direction_unsure" in windows:
        # a side step whose direction the model cannot tell (the phone's placement in a pocket or a
        # swinging hand flips the lateral axis) has no trustworthy lateral update: forward, as out of domain
        unsure = np.array([bool(v) for v in window_values_at_steps(windows, t_look, "side_direction_unsure")], dtype=bool)
        modes = np.where(unsure & np.char.startswith(model_modes, "side_"), "walk", modes)
    return flags, modes, model_modes


def _step_reasons(windows: pd.DataFrame, t_look, n: int) -> np.ndarray | None:
    """The ``out_of_domain_reason`` of the window nearest each step (as its flag), or None when the windows have none."""
    if n == 0 or "out_of_domain_reason" not in windows:
        return None
    return np.array([str(v or "") for v in window_values_at_steps(windows, t_look, "out_of_domain_reason")], dtype=object)


def _detect(recording: Recording, detector):
    """Run a step detector given by name or as an object (a clone: the caller's object is not modified)."""
    from gaitml.steps import get_detector

    det = get_detector(detector) if isinstance(detector, str) else clone(detector)
    det.detect(recording)
    return det.steps_, getattr(det, "segments_", None)


def _heading_source(
    heading, *, attitude, hde, dwpca, initial_heading_rad: float, gyro_bias="auto", gyro_bias_start=None
) -> BaseHeadingSource:
    """A new heading source: a registry name resolved with the optional ``hde`` / ``dwpca`` / ``attitude``
    objects, or a clone of the given source; without an attitude of its own it gets ``attitude`` or
    ``AttitudeEstimator(initial_heading_rad, gyro_bias, start_bias=gyro_bias_start)``. The caller's objects
    are never modified."""
    if isinstance(heading, str):
        if heading not in HEADING_SOURCES:
            raise InputError(f"unknown heading source {heading!r}; use one of {', '.join(HEADING_SOURCES)}.")
        drift = clone(hde) if hde is not None else HeuristicDriftElimination(reference_rad=initial_heading_rad)
        if heading == "gyro":
            src = GyroHeading()
        elif heading == "hde":
            src = drift
        else:
            src = HEADING_SOURCES[heading](**(_dwpca_params(dwpca) if dwpca is not None else {}))
            if heading == "dwpca-hde":
                src.set_params(drift_correction=drift)
    elif isinstance(heading, BaseHeadingSource):
        src = (
            HEADING_SOURCES.get(heading.name, type(heading))(**_dwpca_params(heading))
            if isinstance(heading, DwPcaHeading)
            else clone(heading)
        )
    else:
        raise InputError(f"`heading` must be a heading source name ({', '.join(HEADING_SOURCES)}) or object, got {type(heading).__name__}.")
    if src.attitude is None:
        src.set_params(
            attitude=clone(attitude)
            if attitude is not None
            else AttitudeEstimator(initial_heading_rad=initial_heading_rad, gyro_bias=gyro_bias, start_bias=gyro_bias_start)
        )
    return src


def _dwpca_params(dwpca: DwPcaHeading) -> dict:
    """Parameters of a (fitted) DW-PCA source for a new one; a learned ``polarity_`` becomes ``polarity``."""
    if not isinstance(dwpca, DwPcaHeading):
        raise InputError(f"`dwpca` must be a DwPcaHeading, got {type(dwpca).__name__}.")
    params = clone(dwpca).get_params(deep=False)
    if hasattr(dwpca, "polarity_"):
        params["polarity"] = dict(dwpca.polarity_)
    return params


def _resolve_step_length(step_length) -> tuple[StepLengthModel | None, str]:
    if step_length is None:
        return StepLengthModel(), "defaults (uncalibrated)"
    if isinstance(step_length, StepLengthModel):
        return step_length, "given model"
    if isinstance(step_length, (str, Path)) and str(step_length) == "reference":
        return None, "reference"
    if isinstance(step_length, (str, Path)):
        return StepLengthModel.load(step_length), f"file {step_length}"
    raise InputError(f"`step_length` must be None, a StepLengthModel, a JSON path or 'reference', got {type(step_length).__name__}.")


def calibration_detector_check(step_length: StepLengthModel | None, detector: str | None) -> dict | None:
    """``{"calibrated_with", "detector"}`` when a calibration from truth was fitted on another step detector's steps
    than ``detector`` (the one the PDR runs), else None.

    The true length of a calibration step is the walker's path since the detected step before
    (:func:`gaitml.pdr.calibrate.true_step_lengths`), so the fitted lengths absorb that detector's missed and extra
    steps: with another detector the distance is off by the ratio of the two counts. None too for given steps and
    a model without a record of its detector.
    """
    calibrated = (getattr(step_length, "calibration_", None) or {}).get("detector")
    if not calibrated or detector in (None, "given") or str(calibrated) == str(detector):
        return None
    return {"calibrated_with": str(calibrated), "detector": str(detector)}


def reference_step_lengths(recording: Recording, step_t_s) -> np.ndarray:
    """True length of the nearest reference step (diagnostics: isolates step-length error)."""
    ref = recording.reference.get("steps")
    if ref is None or "step_length_m" not in ref:
        raise InputError("step_length='reference' needs reference['steps'] with step_length_m (a simulated recording).")
    rt = ref["t_s"].to_numpy(float)
    order = np.argsort(rt)
    rt = rt[order]
    rl = ref["step_length_m"].to_numpy(float)[order]
    t = np.asarray(step_t_s, dtype=float)
    j = np.clip(np.searchsorted(rt, t), 1, len(rt) - 1) if len(rt) > 1 else np.zeros(len(t), dtype=int)
    if len(rt) > 1:
        j = np.where(np.abs(t - rt[j - 1]) <= np.abs(rt[j] - t), j - 1, j)
    return rl[j]


def run_pdr(
    recording: Recording,
    *,
    model=None,
    detector=DEFAULT_STEP_DETECTOR,
    steps: pd.DataFrame | None = None,
    heading: str = "hde",
    modes: str = "model",
    mode_boundaries: str = "auto",
    step_length=None,
    update: str | None = None,
    initial_heading_rad: float = 0.0,
    start_xy_m=(0.0, 0.0),
    attitude: AttitudeEstimator | None = None,
    hde: HeuristicDriftElimination | None = None,
    dwpca: DwPcaHeading | None = None,
    gyro_bias="auto",
    gyro_bias_start=None,
    run_min_cadence_hz: float | None = None,
    short_run_windows: float | None = None,
) -> PdrResult:
    """Dead-reckon a recording into a 2-D trajectory.

    Parameters
    ----------
    recording : Recording with acc and gyro.
    model : TrainedModel, optional (needed for ``modes='model'``).
    detector : str or step detector object; default :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`
        (paper 003's ``single-peak`` is one argument away).
        A name is resolved by :data:`gaitml.steps.DETECTORS`; an object is cloned.
    steps : DataFrame, optional; a step table to use instead of running a detector.
    heading : {'hde', 'dwpca', 'gyro', 'dwpca-hde'} or heading source object
        Buffered HDE on the gyro heading (paper 003), DW-PCA step direction (paper 002),
        the raw gyro heading, or DW-PCA followed by HDE (:data:`HEADING_SOURCES`); or a
        configured :class:`~gaitml.pdr.heading.BaseHeadingSource` (cloned).
    modes : {'model', 'true', 'forward'}
        ``model`` requires ``model``; ``true`` requires per-sample labels; ``forward``
        treats every step as a walk step (traditional PDR).
    mode_boundaries : {'auto', 'refine', 'nearest', 'middle'}
        With ``modes='model'``: each step takes the mode of the nearest (corrected)
        window, then ``refine`` re-places every mode change at the most likely step
        (:func:`gaitml.pdr.step_modes.refine_mode_boundaries`, ours); ``nearest`` stops
        after the nearest-window assignment (paper 003 sec. 4.1 as written); ``middle``
        looks up the window nearest the middle between a step time and the next. ``auto``
        (default) refines when the step times are peaks (``t_peak_s``: single-peak,
        adaptive) and keeps ``nearest`` otherwise (the FSM detectors time a step by its
        end, where the nearest window already does better than the refinement).
    step_length : None (stated defaults), StepLengthModel, JSON path, or ``'reference'``
        (nearest true step length from ``reference['steps']``, for diagnostics only). A
        given model is only read (``predict``), so its fitted coefficients are used.
    update : {'multi', 'forward'}, default ``'forward'`` when ``modes='forward'`` else ``'multi'``.
    initial_heading_rad : compass heading at the first sample (no magnetometer).
    start_xy_m : start position.
    attitude, hde, dwpca : configured estimators used with a heading *name* (defaults
        otherwise: ``AttitudeEstimator(initial_heading_rad)``,
        ``HeuristicDriftElimination(reference_rad=initial_heading_rad)``, ``DwPcaHeading()``);
        cloned, never modified.
    gyro_bias : {'auto', 'still', 'off'} or (3,) float, default 'auto'
        Gyroscope bias removed before the attitude and heading (the default attitude's
        ``gyro_bias``, :class:`~gaitml.pdr.attitude.AttitudeEstimator`; ignored when
        ``attitude`` or the heading source brings its own). What was removed is in
        ``info['gyro_bias']``.
    gyro_bias_start : :class:`gaitml.signal.GyroBias`, optional
        A bias measured elsewhere (:func:`gaitml.signal.gyro_bias_from_still` of a still recording of the
        same phone, :func:`gaitml.signal.read_gyro_bias_json`) to start from in place of the recording's own
        still stretches: ``gyro_bias='still'`` holds it, ``'auto'`` tracks it online
        (``AttitudeEstimator(start_bias=...)``).
    run_min_cadence_hz : float, optional
        The model's run-cadence rule (:func:`gaitml.models._predict.run_cadence_rule`): a window read
        ``run`` at a walking step cadence takes the model's best other mode. None:
        :data:`gaitml.models._predict.RUN_CADENCE_DEFAULT_HZ`; 0: off.
    short_run_windows : float, optional
        With ``modes='model'`` and a time-window model, the short-run rule
        (:func:`gaitml.pdr.step_modes.forward_short_runs`): a side or backward run between forward steps
        holding fewer steps than this many model windows at the median step interval takes the forward mode
        before it; ``info['short_run_steps']`` counts them. None: :data:`gaitml.pdr.step_modes.SHORT_RUN_DEFAULT`
        (0, off); elsewhere it has no effect and a note says so.

    Returns
    -------
    PdrResult, with ``info['heading_check']`` the HDE structure guard's record (None without HDE;
    :func:`gaitml.pdr.hde.hde_heading`), ``info['gait_check']`` the step table's gait-evidence account (the default
    ``adaptive`` detector leaves out bouts of steps without gait evidence,
    :mod:`gaitml.steps._gait_evidence`; None when the detector ran no such test) and
    ``info['rate_check']`` its rate check (:func:`gaitml.steps.rate_record`; None for given steps without one).
    """
    if not isinstance(recording, Recording):
        raise InputError(f"`recording` must be a gaitml Recording, got {type(recording).__name__}.")
    source = _heading_source(
        heading,
        attitude=attitude,
        hde=hde,
        dwpca=dwpca,
        initial_heading_rad=initial_heading_rad,
        gyro_bias=gyro_bias,
        gyro_bias_start=gyro_bias_start,
    )
    if modes not in MODE_SOURCES:
        raise InputError(f"unknown mode source {modes!r}; use one of {', '.join(MODE_SOURCES)}.")
    if mode_boundaries not in MODE_ASSIGNMENTS:
        raise InputError(f"unknown mode_boundaries {mode_boundaries!r}; use one of {', '.join(MODE_ASSIGNMENTS)}.")
    update = update or ("forward" if modes == "forward" else "multi")
    if update not in ("multi", "forward"):
        raise InputError(f"`update` must be 'multi' or 'forward', got {update!r}.")
    short_w = short_run_setting(short_run_windows)
    recording.require_gyr("PDR heading")
    fs = recording.sampling_rate_hz
    notes: list[str] = []

    segments = None
    if steps is None:
        steps, segments = _detect(recording, detector)
        det_name = detector if isinstance(detector, str) else type(detector).__name__
    else:
        det_name = "given"
    event = steps.attrs.get("event", "t_peak_s")
    if event not in steps:
        event = "t_peak_s"
    if len(steps) > 1 and np.any(np.diff(steps[event].to_numpy(float)) < 0):
        steps = steps.sort_values(event, kind="stable")
        notes.append(f"the step table was not in time order; sorted by {event}")
    steps = steps.reset_index(drop=True).copy()
    steps.attrs["event"] = event
    gait = gait_check_record(steps.attrs.get("gait_check"))  # before the tables are joined (attrs do not survive)
    rate = rate_record(steps)  # the step detector's rate check (gaitml.steps._rate)
    t_step = steps[event].to_numpy(float)
    start = steps["start"].to_numpy(np.int64)
    end = steps["end"].to_numpy(np.int64)
    n = len(steps)

    # ---- modes per step
    if modes == "true":
        if recording.labels is None:
            raise InputError("modes='true' needs per-sample labels in the recording; use modes='model' with a model, or 'forward'.")
        step_modes = modes_from_labels(recording.labels, start, np.maximum(end, start + 1)) if n else np.zeros(0, dtype=str)
    elif modes == "model":
        if model is None:
            raise InputError("modes='model' needs a model (--model MODEL_DIR); use modes='true' with labels or 'forward'.")
        from gaitml.models import predict_recording

        if getattr(model, "window_by", "time") != "time":  # step-window model: one prediction per step (gaitml.pdr.step_modes)
            step_modes, note, step_flags, step_reasons = modes_from_step_model(
                model, recording, steps, with_reasons=True, run_min_cadence_hz=run_min_cadence_hz
            )
            notes.append(note)
            mode_boundaries = "per-step"
        elif mode_boundaries == "auto":
            mode_boundaries = "refine" if event == "t_peak_s" else "nearest"
            if mode_boundaries == "nearest":
                notes.append(f"step times are {event}, not peaks: modes from the nearest window, without boundary refinement")
        if mode_boundaries != "per-step":
            # read for the steps' modes only: the veto's step finder runs when it can change one (veto_can_change_step_modes)
            windows = predict_recording(model, recording, correction=True, run_min_cadence_hz=run_min_cadence_hz, veto_for_step_modes=True)
            t_look = 0.5 * (t_step + next_step_times(t_step)) if mode_boundaries == "middle" and n > 1 else t_step
            step_modes = modes_from_windows(windows, t_look) if n else np.zeros(0, dtype=str)
            if mode_boundaries == "refine" and n > 1:
                step_modes = refine_mode_boundaries(model, recording, t_step, step_modes)
            step_modes, short_run_steps = _short_runs(step_modes, t_step, model, short_w, notes)
            step_in_domain, step_modes, model_modes = _out_of_domain_steps(model, windows, t_look, step_modes)
            step_reasons = _step_reasons(windows, t_look, n)
        else:  # the step-window model's own per-step flags: out-of-domain steps move forward, as for windows
            model_modes = np.asarray(step_modes).astype(str)
            step_in_domain = np.array([None if v is None else bool(v) for v in step_flags], dtype=object)
            if getattr(model, "domain", None) is not None:
                step_modes = np.where(np.array([v is False for v in step_in_domain], dtype=bool), "walk", model_modes)
    else:
        step_modes = np.full(n, "walk", dtype=object)
    step_modes = np.asarray(step_modes).astype(str)
    if modes != "model" or mode_boundaries == "per-step":
        short_run_steps = None
        short_run_unused(short_w, modes, notes)
    if modes != "model":
        step_in_domain = model_modes = None
    if modes != "model":
        step_reasons = None
    offsets = mode_offsets_rad(step_modes, unknown="forward")
    unknown = sorted(set(step_modes) - {"walk", "run", "side_left", "side_right", "backward", "forward"})
    if unknown:
        notes.append(f"modes {unknown} are not motion modes of paper 003; moved along the heading")

    # ---- step length
    slm, sl_source = _resolve_step_length(step_length)
    feats = step_length_features(recording.acc, steps, fs)
    if slm is None:
        lengths = reference_step_lengths(recording, t_step)
    else:
        lengths = slm.predict(feats, step_modes)
    lengths = np.where(np.isfinite(lengths), lengths, 0.0)
    outside_fit = None if slm is None else slm.outside_fit(feats, step_modes)

    # ---- heading
    heading_steps = steps.assign(mode=step_modes, mode_offset_rad=offsets if update == "multi" else np.zeros(n))
    heading_steps.attrs = dict(steps.attrs)
    if isinstance(source, DwPcaHeading) and segments is not None and len(segments) == n and {"start", "end"} <= set(segments.columns):
        heading_steps = heading_steps.assign(
            window_start=segments["start"].to_numpy(np.int64), window_end=segments["end"].to_numpy(np.int64)
        )
        notes.append("DW-PCA windows: the detector's S2..S6 segments")
    source.estimate(recording, heading_steps)
    gyro_h = source.gyro_heading_rad_
    theta = source.heading_rad_

    return assemble_result(
        steps,
        feats,
        step_modes,
        lengths,
        theta,
        gyro_h,
        update=update,
        start_xy_m=start_xy_m,
        initial_heading_rad=initial_heading_rad,
        step_in_domain=step_in_domain,
        model_modes=model_modes,
        model=model,
        step_reasons=step_reasons,
        outside_fit=outside_fit,
        info={
            "detector": det_name,
            "heading": heading if isinstance(heading, str) else source.name or type(source).__name__,
            "modes": modes,
            "mode_boundaries": mode_boundaries if modes == "model" else None,
            "update": update,
            "step_length": sl_source,
            "initial_heading_rad": float(initial_heading_rad),
            "gyro_bias": _bias_record(source),
            "heading_check": heading_check_record(source),
            "gait_check": gait,
            "rate_check": rate,
            "step_length_detector": calibration_detector_check(slm, det_name),
            "short_run_steps": short_run_steps,
            "notes": notes,
        },
    )


def short_run_setting(short_run_windows) -> float:
    """``run_pdr``'s ``short_run_windows`` checked: None gives :data:`gaitml.pdr.step_modes.SHORT_RUN_DEFAULT`; anything but
    a finite number >= 0 is refused (:class:`~gaitml.errors.InputError`)."""
    w = SHORT_RUN_DEFAULT if short_run_windows is None else short_run_windows
    try:
        w = float(w)
    except (TypeError, ValueError):
        w = float("nan")
    if isinstance(short_run_windows, bool) or not (np.isfinite(w) and w >= 0):
        raise InputError(f"short_run_windows must be a number of model windows >= 0 (0: off), got {short_run_windows!r}.")
    return w


def short_run_unused(w: float, modes: str, notes: list[str]) -> None:
    """A note when the short-run rule was asked for (``w`` > 0) where it cannot act: it reads the per-step modes a
    time-window model's windows give (``modes='model'``), not labels, forward-only steps or a step-window model's own
    per-step modes."""
    if w > 0:
        why = "a step-window model gives each step its own mode" if modes == "model" else f"modes are {modes!r}, not a model's windows"
        notes.append(f"short_run_windows={w:g} (--short-runs) has no effect: {why}; it applies to --model with a time-window model")


def _short_runs(step_modes, t_step, model, w: float, notes: list[str]) -> tuple[np.ndarray, int]:
    """:func:`gaitml.pdr.step_modes.forward_short_runs` with the checked setting ``w`` (:func:`short_run_setting`) and the
    model's window; a note when it moved steps. Returns the new modes and how many steps moved."""
    out, moved = forward_short_runs(step_modes, t_step, model.length_s, w)
    if moved:
        notes.append(
            f"{moved} side or backward steps in runs shorter than {w:g} model window(s) between forward steps moved forward "
            "(paper 003 sec. 3.4 at the step level; --short-runs 0 keeps them)"
        )
    return out, moved


def heading_check_record(source) -> dict | None:
    """The HDE structure guard's record of a heading source that ran HDE (``heading_check_``,
    :func:`gaitml.pdr.hde.hde_heading`), JSON-ready; None for a source without HDE."""
    check = getattr(source, "heading_check_", None)
    return None if check is None else dict(check)


def _bias_record(source) -> dict | None:
    """What the heading source's attitude removed as gyroscope bias (JSON-ready), or None."""
    att = getattr(source, "attitude_", None)
    gb = getattr(att, "gyro_bias_", None)
    return None if gb is None else gb.to_dict()


def assemble_result(
    steps: pd.DataFrame,
    feats: pd.DataFrame,
    step_modes,
    lengths,
    theta,
    gyro_h,
    *,
    update: str,
    start_xy_m,
    initial_heading_rad: float,
    step_in_domain,
    model_modes,
    model,
    info: dict,
    step_reasons=None,
    outside_fit=None,
) -> PdrResult:
    """The positions (multi-state update, paper 003 eq. 11, or forward-only, eq. 10) and the
    :class:`PdrResult` of per-step modes, lengths and headings; shared by :func:`run_pdr` and the
    chunked run of a long recording (:func:`gaitml.chunked_run.long_pdr`), so both give the same
    tables and summary. ``step_reasons``: the ``out_of_domain_reason`` of each step (None: not known);
    the step table gets the column (with ``in_domain``: a step whose ``in_domain`` is None, e.g. every step
    of a model without a domain record, has the reason None, unknown, not the empty reason of a step in domain) and ``info`` the count ``foot_mounted_steps`` of
    :data:`gaitml.models._placement.FOOT_REASON` when the foot-placement rule ran for ``model``. ``outside_fit``:
    per step, whether its step-length inputs lie outside what a calibrated step-length model was fitted on
    (:meth:`~gaitml.pdr.step_length.StepLengthModel.outside_fit`; None: no calibration record), kept as the step
    table's ``step_length_outside_fit`` and counted in ``info['step_length_outside_fit']``."""
    step_modes = np.asarray(step_modes).astype(str)
    if update == "multi":
        xy = multi_state_update(lengths, theta, step_modes, start_xy_m=start_xy_m, unknown="forward")
    else:
        xy = forward_update(lengths, theta, start_xy_m=start_xy_m)
    t_step = steps[steps.attrs.get("event", "t_peak_s")].to_numpy(float)
    traj = pd.DataFrame(
        {
            "t_s": np.concatenate([[0.0], t_step]),
            "x_m": xy[:, 0],
            "y_m": xy[:, 1],
            "heading_rad": np.concatenate([[wrap_angle(initial_heading_rad)], wrap_angle(theta)]),
            "mode": np.concatenate([["start"], step_modes]).astype(object),
            "step_length_m": np.concatenate([[0.0], lengths]),
        }
    )
    if step_in_domain is not None:  # modes from a model: the out-of-domain flag of every step
        traj["in_domain"] = np.concatenate([[None], step_in_domain]).astype(object)
    # steps recorded below the step detector's rate floor (gaitml.steps._rate): the same column as gaitml steps --out
    detected = steps  # the detector's table (its attrs name the step times the rate check reads)
    add_rate_reasons(traj, detected, info.get("rate_check"), leading_rows=1)
    if outside_fit is not None:  # each step's length extrapolated beyond the calibration's inputs, or not
        traj["step_length_outside_fit"] = np.concatenate([[None], np.asarray(outside_fit, dtype=bool)]).astype(object)
    steps = pd.concat([steps, feats], axis=1)
    steps["mode"] = step_modes
    steps["step_length_m"] = lengths
    steps["gyro_heading_rad"] = gyro_h
    steps["heading_rad"] = wrap_angle(theta)
    if step_in_domain is not None:
        steps["mode_model"] = model_modes
        steps["in_domain"] = step_in_domain
    n_ood = (
        None
        if step_in_domain is None or getattr(model, "domain", None) is None
        else int(sum(v is False or v is np.False_ for v in step_in_domain))
    )
    n_unsure = (
        None
        if n_ood is None
        else int(
            np.sum(
                np.char.startswith(np.asarray(model_modes).astype(str), "side_")
                & (np.asarray(step_modes).astype(str) == "walk")
                & np.array([v is True or v is np.True_ for v in step_in_domain], dtype=bool)
            )
        )
    )
    info = {**info, "out_of_domain_steps": n_ood, "side_direction_unsure_steps": n_unsure}
    add_rate_reasons(steps, detected, info.get("rate_check"))
    if outside_fit is not None:
        steps["step_length_outside_fit"] = np.asarray(outside_fit, dtype=bool)
        info["step_length_outside_fit"] = int(np.sum(outside_fit))
    if step_reasons is not None and step_in_domain is not None:
        from gaitml.models._placement import FOOT_REASON
        from gaitml.models._predict import foot_rule_applies

        reasons = np.asarray(step_reasons, dtype=object).copy()
        reasons[np.array([v is None for v in step_in_domain], dtype=bool)] = None
        steps["out_of_domain_reason"] = reasons
        if foot_rule_applies(model):  # a count only where the rule ran (not: no domain record, a foot in training)
            info["foot_mounted_steps"] = int(sum(str(r) == FOOT_REASON for r in step_reasons))
    info = {k: info[k] for k in (*[k for k in info if k != "notes"], "notes")}
    return PdrResult(
        trajectory=traj,
        steps=steps,
        distance_m=float(np.sum(lengths)),
        end_xy_m=(float(xy[-1, 0]), float(xy[-1, 1])),
        info=info,
    )
