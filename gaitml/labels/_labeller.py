"""The labeller: intervals to per-sample and per-step labels, boundaries snapped to steps or strides."""

from __future__ import annotations

import os
from typing import Any, ClassVar

import numpy as np
import pandas as pd

from gaitml._base import NON_NEGATIVE, POSITIVE, BaseAlgorithm, Options
from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.labels._evidence import change_at, step_character
from gaitml.labels._intervals import check_intervals, read_intervals
from gaitml.recording import Recording
from gaitml.steps._rate import add_rate_reasons, rate_record
from gaitml.steps._table import gait_check_record

__all__ = ["BOUNDARY_KINDS", "SNAP_MODES", "SNAP_RULES", "UNLABELLED", "IntervalLabeller", "label_recording"]

#: Values of ``snap``.
SNAP_MODES = ("steps", "strides", "none")
#: Label of samples outside every interval.
UNLABELLED = "unlabelled"
#: Values of ``boundary`` (step snapping).
BOUNDARY_KINDS = ("peak", "edges")
#: Values of ``rule``: move a boundary to the evidence of the mode change, or to the nearest step boundary.
SNAP_RULES = ("change", "nearest")


def _to_sample(t_s: np.ndarray | float, fs: float) -> np.ndarray:
    """First sample at or after ``t_s`` (half-open intervals ``[start, end)`` in samples)."""
    return np.ceil(np.asarray(t_s, dtype=float) * fs - 1e-6).astype(int)


# ------------------------------------------------------------ candidates
def _step_candidates(rec: Recording, detector: str, boundary: str) -> tuple[np.ndarray, pd.DataFrame, np.ndarray, np.ndarray]:
    """(candidate boundary samples, step table, span starts, span ends) of a step detector."""
    from gaitml.steps import get_detector

    try:
        algo = get_detector(detector)
    except InputError as exc:
        raise InputError(f"{str(exc).rstrip('.')} (--snap steps/none takes a step detector).") from None
    steps = algo.detect(rec).steps_
    n = rec.n_samples
    if len(steps) == 0:
        return np.zeros(0, dtype=int), steps, np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    if boundary == "peak":
        peaks = steps["peak"].to_numpy(dtype=int)
        cand = np.clip(peaks + 1, 0, n)
        span_start = np.concatenate([[int(steps["start"].iloc[0])], cand[:-1]])
        span_end = cand
    else:
        span_start = steps["start"].to_numpy(dtype=int)
        span_end = np.clip(steps["end"].to_numpy(dtype=int), 0, n)
        cand = np.unique(np.concatenate([span_start, span_end]))
    return np.unique(cand), steps, span_start, np.maximum(span_end, span_start + 1)


def _stride_candidates(rec: Recording, detector: str) -> tuple[np.ndarray, pd.DataFrame, np.ndarray, np.ndarray]:
    from gaitml.zupt import get_detector, segment_strides

    try:
        algo = get_detector(detector)
    except InputError as exc:
        raise InputError(f"{str(exc).rstrip('.')} (--snap strides takes a zero-velocity detector).") from None
    rec.require_gyr("--snap strides (zero-velocity detection)", "use --snap steps for a phone recording")
    zupts = algo.detect(rec).zupts_
    strides = segment_strides(zupts, rec.sampling_rate_hz)
    if len(strides) == 0:
        return np.zeros(0, dtype=int), strides, np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    s = strides["start"].to_numpy(dtype=int)
    e = strides["end"].to_numpy(dtype=int)
    return np.unique(np.concatenate([s, e])), strides, s, e


#: the step detector's own timing error (s): added to the stated noise for the search band; rule change makes no smaller move
STEP_TIMING_TOLERANCE_S = 0.1
#: a step interval over this many times its neighbour hides a missed step (a missed step doubles the interval)
MISSED_STEP_RATIO = 1.8


# ------------------------------------------------------------------ labeller


class IntervalLabeller(BaseAlgorithm):
    """Label a recording's samples and steps from time intervals, snapping boundaries to steps or strides.

    Parameters
    ----------
    snap : {'steps', 'strides', 'none'}
        What boundaries move to (see the module doc).
    detector : str, optional
        The step detector (``snap`` steps/none; default :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`) or the
        zero-velocity detector (``snap`` strides; default ``pseudo-std``).
    max_snap_s : float
        Largest move of a boundary in s (default 0.5 s, about one walking
        step); a boundary farther from every candidate stays and is reported.
    unlabelled : str
        Label of samples outside every interval (default ``'unlabelled'``).
    boundary : {'peak', 'edges'}
        Step boundaries at the step events (default) or at the detector's step
        start/end samples.
    noise_s : float, optional
        The most a written boundary is off (s): the search band is ``noise_s``
        plus ``STEP_TIMING_TOLERANCE_S`` (0.1 s), at most ``max_snap_s``.
        Default: ``max_snap_s``. With ``rule='nearest'``, a boundary is snapped
        only when exactly one candidate lies within the band and the step
        intervals on either side of it are regular (neither over
        ``MISSED_STEP_RATIO`` = 1.8 times the other: a missed step may be the
        true boundary); otherwise it stays (status ``ambiguous``).
    rule : {'change', 'nearest'}
        ``'change'`` (default): a boundary moves only to evidence of the mode
        change itself (:mod:`gaitml.labels._evidence`): the end of the last
        step of the old mode before the first step whose character (duration,
        intensity, per-axis acceleration spread) departs from it towards the
        new mode, found within the search band; the old and the new mode must
        each be described by at least four steps outside the band, the change
        must be clean (the last old step like the old mode, the two steps
        after it departing, no step hiding a missed one, the detector not
        counting strides), and a move shorter than the detector's timing
        (``STEP_TIMING_TOLERANCE_S``) is not made (status ``within timing``). Anything
        else stays where it was written (status ``ambiguous``). ``'nearest'``:
        the nearest candidate within ``max_snap_s`` (or the unique one within
        the stated noise); it moves more boundaries and can move one the
        wrong way.

    Attributes
    ----------
    recording_ : Recording
        The input with the new per-sample ``labels`` (previous labels replaced).
    intervals_ : DataFrame
        One row per interval: ``label``, ``start_s``, ``end_s`` (as written),
        ``snapped_start_s``, ``snapped_end_s``, ``start_shift_s``,
        ``end_shift_s``, ``line``.
    boundaries_ : DataFrame
        One row per distinct boundary: ``t_s`` (as written), ``snapped_t_s``,
        ``shift_s``, ``status`` (``snapped``, ``too far``, ``recording edge``,
        ``no candidates``, ``collapsed``, ``ambiguous``, ``within timing`` (rule change: within the
        detector's timing), ``not snapped`` for snap none).
    steps_ : DataFrame
        One row per detected step (or stride): ``t_s`` (the step event / stride
        start), ``span_start_s``, ``span_end_s`` (the samples the step covers,
        ``[start, end)``), ``label`` (the majority label of those samples) and
        ``label_fraction`` (its share; 1 when a step lies inside one interval); ``rate_reason`` when a step was
        recorded below the step detector's rate floor (:func:`gaitml.steps.rate_flags`; the column is there only then).
    report_ : dict
        Counts for a summary: ``n_intervals``, ``n_boundaries``, ``n_snapped``,
        ``not_snapped`` (list of ``[t_s, status]``), ``mean_abs_shift_s``,
        ``max_abs_shift_s``, ``n_unlabelled_samples``, ``n_steps``,
        ``n_mixed_steps`` (label_fraction < 1), ``snap``, ``detector``,
        ``max_snap_s``, ``boundary``, ``noise_s``, ``rule``, and ``gait_check``: the step
        detector's gait-evidence account (steps left out in bouts without gait evidence,
        :func:`gaitml.steps._gait_evidence.gait_check`; None for strides and for a detector
        that ran no such test), ``rate_check``: the step detector's rate check (:func:`gaitml.steps.rate_record`: was
        the recording made below the lowest rate its count holds at? None for strides).
    """

    _action_method = "label"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "snap": [Options(SNAP_MODES)],
        "max_snap_s": [NON_NEGATIVE],
        "boundary": [Options(BOUNDARY_KINDS)],
        "noise_s": [None, POSITIVE],
        "rule": [Options(SNAP_RULES)],
    }

    def __init__(
        self,
        *,
        snap: str = "steps",
        detector: str | None = None,
        max_snap_s: float = 0.5,
        unlabelled: str = UNLABELLED,
        boundary: str = "peak",
        noise_s: float | None = None,
        rule: str = "change",
    ):
        self.snap = snap
        self.detector = detector
        self.max_snap_s = max_snap_s
        self.unlabelled = unlabelled
        self.boundary = boundary
        self.noise_s = noise_s
        self.rule = rule

    def label(self, recording: Recording, intervals: pd.DataFrame | str | os.PathLike) -> IntervalLabeller:
        """Label ``recording`` from ``intervals`` (a DataFrame or an intervals file); returns ``self``."""
        self._validate_params()
        if not str(self.unlabelled).strip():
            raise InputError("the unlabelled label must be a non-empty string; pass e.g. 'unlabelled'.")
        rec = recording
        fs = rec.sampling_rate_hz
        n = rec.n_samples
        iv = read_intervals(intervals) if isinstance(intervals, str | os.PathLike) else intervals
        iv = check_intervals(iv, rec.duration_s, fs)

        if self.snap == "strides":
            det = self.detector or "pseudo-std"
            cand, units, span_s, span_e = _stride_candidates(rec, det)
        else:
            det = self.detector or DEFAULT_STEP_DETECTOR
            cand, units, span_s, span_e = _step_candidates(rec, det, self.boundary)

        # distinct boundaries (touching intervals share one), in samples
        b_t = np.unique(np.concatenate([iv["start_s"].to_numpy(), iv["end_s"].to_numpy()]))
        b_k = np.clip(_to_sample(b_t, fs), 0, n)
        new_k = b_k.copy()
        status = np.array(["not snapped"] * len(b_t), dtype=object)
        if self.snap != "none" and self.rule == "change":
            max_k = self.max_snap_s * fs + 1e-6
            band = max_k if self.noise_s is None else min(max_k, (self.noise_s + STEP_TIMING_TOLERANCE_S) * fs + 1e-6)
            feats = step_character(rec.acc, span_s, span_e, fs)
            for i, k in enumerate(b_k):
                if k <= 0 or k >= n:
                    status[i] = "recording edge"
                elif len(span_e) == 0:
                    status[i] = "no candidates"
                else:
                    k_prev = float(b_k[i - 1]) if i > 0 else 0.0
                    k_next = float(b_k[i + 1]) if i + 1 < len(b_k) else float(n)
                    at, status[i] = change_at(feats, span_e, int(k), band, k_prev, k_next)
                    if at is not None and abs(at - k) < STEP_TIMING_TOLERANCE_S * fs:
                        status[i] = "within timing"  # within the detector's own timing: the move says nothing
                    elif at is not None:
                        new_k[i] = at
        elif self.snap != "none":
            max_k = self.max_snap_s * fs + 1e-6
            for i, k in enumerate(b_k):
                if k <= 0 or k >= n:
                    status[i] = "recording edge"
                    continue
                if len(cand) == 0:
                    status[i] = "no candidates"
                    continue
                j = int(np.searchsorted(cand, k))
                opts = [c for c in (cand[j - 1] if j > 0 else None, cand[j] if j < len(cand) else None) if c is not None]
                best = min(opts, key=lambda c: (abs(c - k), c))
                if self.noise_s is not None:
                    # the true boundary is a step boundary within noise_s (plus the detector's timing error) of the
                    # written one: snap only when exactly one candidate lies there (two or more: the written time
                    # cannot tell which) and the steps around it are regular (an interval over MISSED_STEP_RATIO
                    # times its neighbour hides a missed step, which may be the true boundary): otherwise it stays
                    band = (self.noise_s + STEP_TIMING_TOLERANCE_S) * fs + 1e-6
                    inside = cand[(cand >= k - band) & (cand <= k + band)]
                    if len(inside) != 1 or abs(best - k) > max_k:
                        status[i] = "ambiguous" if len(inside) > 1 else "too far"
                        continue
                    c = int(np.searchsorted(cand, best))
                    if 0 < c < len(cand) - 1:
                        left, right = cand[c] - cand[c - 1], cand[c + 1] - cand[c]
                        if max(left, right) > MISSED_STEP_RATIO * min(left, right):
                            status[i] = "ambiguous"
                            continue
                if abs(best - k) <= max_k:
                    new_k[i] = best
                    status[i] = "snapped"
                else:
                    status[i] = "too far"
        if self.snap != "none":
            # two boundaries onto one sample would empty an interval: keep both where written
            for i in range(1, len(new_k)):
                if new_k[i] <= new_k[i - 1] and b_k[i] > b_k[i - 1]:
                    for j in (i - 1, i):
                        new_k[j] = b_k[j]
                        status[j] = "collapsed"
        where = {float(t): int(k) for t, k in zip(b_t, new_k, strict=True)}

        labels = np.full(n, str(self.unlabelled), dtype=object)
        rows = []
        for row in iv.itertuples():
            k0, k1 = where[float(row.start_s)], where[float(row.end_s)]
            labels[k0:k1] = row.label
            rows.append(
                {
                    "label": row.label,
                    "start_s": row.start_s,
                    "end_s": row.end_s,
                    "snapped_start_s": k0 / fs,
                    "snapped_end_s": k1 / fs,
                    "start_shift_s": k0 / fs - row.start_s,
                    "end_shift_s": k1 / fs - row.end_s,
                    "line": row.line,
                }
            )
        labels = labels.astype(str)
        self.intervals_ = pd.DataFrame(rows)
        shift = new_k / fs - b_t
        self.boundaries_ = pd.DataFrame(
            {"t_s": b_t, "snapped_t_s": new_k / fs, "shift_s": np.where(status == "snapped", shift, 0.0), "status": status}
        )
        self.steps_ = self._unit_table(units, span_s, span_e, labels, fs)
        if self.snap != "strides" and len(units) == len(self.steps_):
            add_rate_reasons(self.steps_, units)
        self.recording_ = rec.replace(
            labels=labels, meta={**rec.meta, "labelled_from": iv.attrs.get("source", "intervals"), "label_snap": self.snap}
        )
        snapped = status == "snapped"
        real = status != "recording edge"
        self.report_ = {
            "snap": self.snap,
            "detector": det,
            "boundary": self.boundary if self.snap != "strides" else "stride start",
            "max_snap_s": float(self.max_snap_s),
            "noise_s": None if self.noise_s is None else float(self.noise_s),
            "rule": self.rule,
            "n_intervals": int(len(iv)),
            "n_boundaries": int(real.sum()),
            "n_snapped": int(snapped.sum()),
            "not_snapped": [[float(t), str(s)] for t, s in zip(b_t, status, strict=True) if s not in ("snapped", "recording edge")],
            "mean_abs_shift_s": float(np.mean(np.abs(shift[snapped]))) if snapped.any() else 0.0,
            "max_abs_shift_s": float(np.max(np.abs(shift[snapped]))) if snapped.any() else 0.0,
            "n_unlabelled_samples": int((labels == str(self.unlabelled)).sum()),
            "n_steps": int(len(self.steps_)),
            "n_mixed_steps": int((self.steps_["label_fraction"] < 1.0).sum()) if len(self.steps_) else 0,
            "labels": {str(k): int(v) for k, v in zip(*np.unique(labels, return_counts=True), strict=True)},
            "gait_check": gait_check_record(units.attrs.get("gait_check")) if self.snap != "strides" else None,
            "rate_check": rate_record(units) if self.snap != "strides" else None,
        }
        return self

    def _unit_table(self, units: pd.DataFrame, span_s: np.ndarray, span_e: np.ndarray, labels: np.ndarray, fs: float) -> pd.DataFrame:
        kind = "stride" if self.snap == "strides" else "step"
        rows = []
        for i in range(len(span_s)):
            seg = labels[span_s[i] : span_e[i]]
            if len(seg) == 0:
                lab, frac = labels[min(span_s[i], len(labels) - 1)], 1.0
            else:
                vals, counts = np.unique(seg, return_counts=True)
                lab, frac = vals[int(np.argmax(counts))], float(counts.max() / len(seg))
            t_event = float(units["t_peak_s"].iloc[i]) if kind == "step" else float(units["t_start_s"].iloc[i])
            rows.append(
                {
                    kind: i,
                    "t_s": t_event,
                    "span_start_s": span_s[i] / fs,
                    "span_end_s": span_e[i] / fs,
                    "label": str(lab),
                    "label_fraction": round(frac, 6),
                }
            )
        cols = [kind, "t_s", "span_start_s", "span_end_s", "label", "label_fraction"]
        return pd.DataFrame(rows, columns=cols)


def label_recording(recording: Recording, intervals: pd.DataFrame | str | os.PathLike, **params: Any) -> IntervalLabeller:
    """Run :class:`IntervalLabeller` with ``params`` and return it (``recording_``, ``steps_``, ``report_``...)."""
    try:
        lab = IntervalLabeller(**params)
    except TypeError as exc:
        raise InputError(f"bad labelling parameters: {exc}; see help(gaitml.labels.IntervalLabeller).") from None
    return lab.label(recording, intervals)
