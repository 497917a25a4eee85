"""Per-subject calibration of the PDR from a recording with known steps.

Paper 003 sec. 4.1 obtains the step length constants "by training". Here a calibration
recording of the subject whose ``reference['steps']`` carries the true step events (times,
modes, lengths, facing headings; the simulator writes them, a survey-measured walk can be
converted to them) gives:

- a :class:`~gaitml.pdr.step_length.StepLengthModel` fitted per mode by least squares;
- the per-mode polarity of the DW-PCA concavity rule (:meth:`DwPcaHeading.fit_polarity`).

:func:`calibrate_walk_distance` covers the simpler case of a walk of known total distance
(no per-step truth): it rescales a step length model.

:func:`calibrate_from_truth` covers recordings that carry a dense truth trajectory instead of
true step events (motion capture: a tyrex recording's ``--truth self``; a ``t,x_m,y_m`` CSV as
``gaitml pdr --truth`` reads; a simulated recording's reference path), several at once, with
the mode of each recording's steps given by the caller (``walk``, ``run``, ... or the
recording's own ``labels``). The true length of a detected step is the distance the walker's
body (the truth low-passed, :func:`gaitml.signal.body_track`) moves from the previous detected
step to it (:func:`true_step_lengths`); pairs across a pause, a lost stretch of the truth or a
sensor gap (recordings are read in segments) get none. Then, per mode, paper 003 sec. 4.1:
walk (and side, backward) steps fit the linear model of eq. (12) by least squares, run steps
the Weinberg constant K of eq. (13) (:meth:`StepLengthModel.fit`). The least-squares linear fit
has an intercept, so on the steps it was fitted on it sums to the true distance (the walked
distance ratio is 1 in sample); what it gives on other people is the held-out question
(``experiments/reports/tyrex-pdr.md``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.pdr.attitude import AttitudeEstimator
from gaitml.pdr.dwpca import DwPcaHeading
from gaitml.pdr.step_length import FEATURE_COLUMNS, StepLengthModel, step_length_features
from gaitml.pdr.update import mode_offsets_rad
from gaitml.recording import Recording
from gaitml.signal import BODY_CUTOFF_HZ, body_track

__all__ = [
    "CALIBRATION_MODES",
    "Calibration",
    "calibrate_from_reference",
    "calibrate_from_truth",
    "calibrate_walk_distance",
    "fit_step_lengths",
    "match_reference_steps",
    "step_length_samples",
    "true_step_lengths",
    "truth_track",
]

#: Detected and true step events closer than this are the same step.
MATCH_TOLERANCE_S = 0.15
#: Consecutive detected steps further apart than this (s) follow a pause or missed steps: the later
#: one gets no true length (walking cadence is 1.5-2.5 steps/s; 1.5 s is a pause, not a step).
MAX_STEP_INTERVAL_S = 1.5
#: A run of lost truth positions (NaN: markers out of sight) longer than this (s) is a gap: the
#: body track is filled linearly across it (a chord), so a step pair spanning it gets no true length.
MAX_TRUTH_GAP_S = 0.5
#: Fewest steps with a true length a mode needs to be fitted from truth (three coefficients of
#: eq. 12 from at least ~10 s of walking; stated, not from the paper).
MIN_CALIBRATION_STEPS = 20
#: A stretch between sensor gaps shorter than this (s) is left out of a calibration from truth (a few steps
#: at most, and shorter than the detectors' own windows); said on stderr.
MIN_SEGMENT_S = 5.0
#: The modes a recording's steps can be given as (paper 003's five), or ``labels``: the recording's
#: own per-sample labels, majority over each step (a simulated or labelled recording).
CALIBRATION_MODES = ("walk", "run", "backward", "side_left", "side_right", "labels")
#: The motion modes of paper 003 (a labelled step of another class, e.g. standing, is not fitted).
MOTION_MODES = CALIBRATION_MODES[:-1]


class Calibration:
    """Result of :func:`calibrate_from_reference`: ``step_length`` model, ``dwpca`` estimator, ``n_matched``."""

    def __init__(self, step_length: StepLengthModel, dwpca: DwPcaHeading, n_matched: int, n_detected: int):
        self.step_length = step_length
        self.dwpca = dwpca
        self.n_matched = n_matched
        self.n_detected = n_detected


def match_reference_steps(step_t_s, ref_t_s, *, tolerance_s: float = MATCH_TOLERANCE_S) -> np.ndarray:
    """Index of the nearest reference step for each detected step, -1 when none is within ``tolerance_s``."""
    t = np.asarray(step_t_s, dtype=float)
    r = np.asarray(ref_t_s, dtype=float)
    if len(r) == 0:
        return np.full(len(t), -1)
    order = np.argsort(r)
    rs = r[order]
    j = np.searchsorted(rs, t)
    lo = np.clip(j - 1, 0, len(rs) - 1)
    hi = np.clip(j, 0, len(rs) - 1)
    pick = np.where(np.abs(t - rs[lo]) <= np.abs(rs[hi] - t), lo, hi)
    ok = np.abs(rs[pick] - t) <= tolerance_s
    return np.where(ok, order[pick], -1)


def calibrate_from_reference(recording: Recording, *, detector=DEFAULT_STEP_DETECTOR, min_steps: int = 5) -> Calibration:
    """Fit the step length model and the DW-PCA polarity on a recording with true steps.

    Parameters
    ----------
    recording : Recording with gyro and ``reference['steps']`` (``t_s``, ``mode``,
        ``step_length_m``, ``heading_rad``) and ``reference['trajectory']`` (for the initial heading).
    detector : step detector name or object (the one the PDR will use; default the PDR's own default,
        :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`).
    """
    from gaitml.pdr.pipeline import _detect

    ref = recording.reference.get("steps")
    need = ("t_s", "mode", "step_length_m", "heading_rad")
    if ref is None or any(c not in ref for c in need):
        raise InputError(f"calibration needs reference['steps'] with columns {need}; use a simulated or surveyed recording.")
    steps, _ = _detect(recording, detector)
    event = steps.attrs.get("event", "t_peak_s")
    idx = match_reference_steps(steps[event].to_numpy(float), ref["t_s"].to_numpy(float))
    ok = idx >= 0
    if ok.sum() < min_steps:
        raise InputError(f"only {int(ok.sum())} detected steps match the reference; check the detector suits the recording.")
    st = steps[ok].reset_index(drop=True)
    r = ref.iloc[idx[ok]].reset_index(drop=True)
    modes = r["mode"].astype(str).to_numpy()
    feats = step_length_features(recording.acc, st, recording.sampling_rate_hz)
    slm = StepLengthModel().fit(feats, r["step_length_m"].to_numpy(float), modes, min_steps=min_steps)
    traj = recording.reference.get("trajectory")
    h0 = float(traj["heading_rad"].iloc[0]) if traj is not None and len(traj) else float(r["heading_rad"].iloc[0])
    att = AttitudeEstimator(initial_heading_rad=h0).estimate(recording)
    lin = att.linear_acc_nav(recording)[:, :2]
    motion = r["heading_rad"].to_numpy(float) + mode_offsets_rad(modes, unknown="forward")
    end = np.maximum(st["end"].to_numpy(np.int64), st["start"].to_numpy(np.int64) + 1)
    learned = DwPcaHeading().fit_polarity(lin, st["start"].to_numpy(np.int64), end, motion, modes, min_steps=min_steps).polarity_
    dw = DwPcaHeading(polarity=learned)
    return Calibration(slm, dw, int(ok.sum()), len(steps))


def calibrate_walk_distance(
    recording: Recording, distance_m: float, *, model: StepLengthModel | None = None, detector=DEFAULT_STEP_DETECTOR, mode: str = "walk"
) -> StepLengthModel:
    """Per-subject calibration from a walk of known distance (every step taken as ``mode``).

    The model's coefficients for ``mode`` are scaled so that the detected steps sum to
    ``distance_m`` (see :meth:`StepLengthModel.calibrate`).
    """
    from gaitml.pdr.pipeline import _detect

    steps, _ = _detect(recording, detector)
    if len(steps) == 0:
        raise InputError("no steps detected in the calibration walk; check the recording and the detector.")
    feats = step_length_features(recording.acc, steps, recording.sampling_rate_hz)
    return (model or StepLengthModel()).calibrate(feats, np.full(len(steps), mode), distance_m)


def true_step_lengths(t_step_s, true_t_s, body_xy, *, lost=None, max_interval_s: float = MAX_STEP_INTERVAL_S) -> np.ndarray:
    """Body path length walked between each detected step and the one before (m).

    Parameters
    ----------
    t_step_s : (n,) step times (s), increasing, on the truth's time base.
    true_t_s, body_xy : the walker's track, (m,) times and (m, 2) positions (:func:`gaitml.signal.body_track`).
    lost : (m,) bool, optional
        Truth frames whose position was lost; a run of them longer than
        :data:`MAX_TRUTH_GAP_S` voids the step pairs that span it.
    max_interval_s : float
        Steps further apart than this follow a pause: no length.

    Returns
    -------
    ndarray, shape (n,)
        NaN for the first step, after a pause, across a truth gap and outside the truth.
    """
    t = np.asarray(t_step_s, dtype=float).reshape(-1)
    tt = np.asarray(true_t_s, dtype=float).reshape(-1)
    body = np.asarray(body_xy, dtype=float)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(body, axis=0), axis=1))])
    s = np.interp(t, tt, cum, left=np.nan, right=np.nan)
    out = np.full(len(t), np.nan)
    if len(t) > 1:
        out[1:] = np.diff(s)
        out[1:][np.diff(t) > max_interval_s] = np.nan
        if lost is not None:
            for a, b in _lost_runs(tt, np.asarray(lost, dtype=bool), MAX_TRUTH_GAP_S):
                out[1:][(t[:-1] < b) & (t[1:] > a)] = np.nan
    return out


def _lost_runs(t: np.ndarray, lost: np.ndarray, min_s: float) -> list[tuple[float, float]]:
    """(start, end) times of the runs of lost frames longer than ``min_s``, from the last good frame before to the first after."""
    if not lost.any():
        return []
    edges = np.diff(np.concatenate([[0], lost.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # run = [start, end)
    out = []
    for a, b in zip(starts, ends, strict=True):
        ta, tb = t[max(a - 1, 0)], t[min(b, len(t) - 1)]
        if tb - ta > min_s:
            out.append((float(ta), float(tb)))
    return out


def truth_track(recording: Recording, truth="self") -> tuple[np.ndarray, np.ndarray, str]:
    """A dense truth trajectory of a recording on its time base: times (s), positions (m, NaN where lost), a name.

    Parameters
    ----------
    recording : Recording
    truth : ``'self'``, a file, or ``(t_s, xy)``
        ``'self'``: a tyrex recording's motion capture (:func:`gaitml.io.tyrex.read_tyrex_truth`), else
        the recording's reference trajectory (the simulator's ``<id>.trajectory.csv``). A file: a tyrex
        motion-capture CSV (for a tyrex recording) or a truth CSV ``t,x_m,y_m`` (:func:`gaitml.io.truth.read_truth`)
        on the recording's own clock. ``(t_s, xy)``: arrays already on the recording's time base.

    Raises
    ------
    InputError
        No truth, or a truth of sparse landmarks (per-step lengths need a dense path).
    """
    from gaitml.io.truth import dense_truth

    if isinstance(truth, tuple) and len(truth) == 2:
        return np.asarray(truth[0], dtype=float), np.asarray(truth[1], dtype=float)[:, :2], "given"
    return dense_truth(recording, str(truth))  # the one choice of the truth source, with gaitml pdr --truth's scoring view


def step_length_samples(
    recording: Recording,
    mode: str = "walk",
    *,
    truth="self",
    detector=DEFAULT_STEP_DETECTOR,
    steps: pd.DataFrame | None = None,
    cutoff_hz: float = BODY_CUTOFF_HZ,
) -> pd.DataFrame:
    """The detected steps of a recording with their step-length inputs and true lengths.

    Parameters
    ----------
    recording : Recording
    mode : one of :data:`CALIBRATION_MODES`
        The mode of every step (``labels``: the recording's per-sample labels, majority over each step).
    truth : see :func:`truth_track`.
    detector : the step detector (name or object) the PDR will use; default :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`.
    steps : a step table to use instead of running the detector.
    cutoff_hz : the body track's low-pass (:data:`gaitml.signal.BODY_CUTOFF_HZ`).

    Returns
    -------
    DataFrame, one row per detected step: ``t_s``, ``mode``, the features of
    :func:`~gaitml.pdr.step_length.step_length_features` and ``true_length_m``
    (NaN where :func:`true_step_lengths` gives none), ``recording``.
    """
    from gaitml.pdr.pipeline import _detect, modes_from_labels

    if mode not in CALIBRATION_MODES:
        raise InputError(f"unknown step mode {mode!r}; use one of {', '.join(CALIBRATION_MODES)}.")
    if mode == "labels" and recording.labels is None:
        raise InputError(f"--mode labels needs per-sample labels but {recording.name} has none; give its mode (--mode walk or run).")
    t_true, xy, truth_name = truth_track(recording, truth)
    lost = ~np.isfinite(xy).all(axis=1)
    try:
        body = body_track(t_true, xy, cutoff_hz=cutoff_hz)
    except InputError as exc:  # name the input whose truth it is (several are calibrated at once)
        raise InputError(f"the truth of {recording.name} ({truth_name}): {exc}") from None
    if steps is None:
        steps, _ = _detect(recording, detector)
    event = steps.attrs.get("event", "t_peak_s")
    steps = steps.sort_values(event, kind="stable").reset_index(drop=True) if len(steps) else steps.reset_index(drop=True)
    t_step = steps[event].to_numpy(float) if len(steps) else np.zeros(0)
    feats = step_length_features(recording.acc, steps, recording.sampling_rate_hz).reset_index(drop=True)
    if mode == "labels":
        start = steps["start"].to_numpy(np.int64)
        modes = modes_from_labels(recording.labels, start, np.maximum(steps["end"].to_numpy(np.int64), start + 1)) if len(steps) else []
    else:
        modes = np.full(len(steps), mode)
    return pd.DataFrame(
        {
            "t_s": t_step,
            "mode": np.asarray(modes, dtype=object).astype(str),
            **{c: feats[c].to_numpy(float) for c in feats.columns},
            "true_length_m": true_step_lengths(t_step, t_true, body, lost=lost),
            "recording": recording.name,
        }
    )


def fit_step_lengths(samples: pd.DataFrame, *, modes=None, min_steps: int = MIN_CALIBRATION_STEPS) -> StepLengthModel:
    """Fit a :class:`~gaitml.pdr.step_length.StepLengthModel` per mode on steps with true lengths.

    Paper 003 sec. 4.1: walk, side and backward steps fit eq. (12) ``L = A + B f + C var(a)`` by
    least squares; run steps eq. (13) ``L = K (a_max - a_min)^(1/4)`` (K by least squares).
    Modes not in ``samples`` keep the stated defaults.

    Parameters
    ----------
    samples : DataFrame from :func:`step_length_samples` (concatenated over recordings).
    modes : the modes that must be fitted (default: every mode in ``samples``).
    min_steps : fewest steps with a true length per mode.

    Returns
    -------
    StepLengthModel with ``coefficients_``, ``fitted_modes_`` and ``calibration_`` (per mode: steps,
    recordings, mean true length, RMS residual, fitted over true total on these steps).

    Raises
    ------
    InputError
        No samples; a mode with no steps; a mode with fewer than ``min_steps`` steps with a true length.
    """
    need = ("mode", "true_length_m", *FEATURE_COLUMNS)
    if not isinstance(samples, pd.DataFrame) or any(c not in samples for c in need):
        raise InputError(f"`samples` must be a DataFrame with columns {list(need)}; build it with step_length_samples().")
    if not len(samples):
        raise InputError("no steps were detected in the calibration recordings; check the recordings and the step detector.")
    modes = sorted(set(samples["mode"].astype(str))) if modes is None else list(modes)
    feats = samples[list(FEATURE_COLUMNS)].astype(float).reset_index(drop=True)
    true = samples["true_length_m"].to_numpy(float)
    mode_arr = samples["mode"].astype(str).to_numpy()
    ok = np.isfinite(true) & np.isfinite(feats.to_numpy()).all(axis=1) & (true > 0)
    info = {}
    for m in modes:
        sel = mode_arr == m
        if not sel.any():
            raise InputError(
                f"no steps of mode {m!r} in the calibration recordings; give a recording of {m} (--mode {m}) or drop the mode."
            )
        n_ok = int((sel & ok).sum())
        if n_ok < min_steps:
            raise InputError(
                f"only {n_ok} of {int(sel.sum())} detected {m} steps have a true length (the truth covers them and they are not "
                f"after a pause); at least {min_steps} are needed: add {m} recordings or check that the truth is on the recording's clock."
            )
    keep = ok & np.isin(mode_arr, modes)
    model = StepLengthModel().fit(feats[keep].reset_index(drop=True), true[keep], mode_arr[keep], min_steps=min_steps)
    pred = model.predict(feats[keep].reset_index(drop=True), mode_arr[keep])
    recs = samples["recording"].astype(str).to_numpy() if "recording" in samples else np.full(len(samples), "")
    for m in modes:
        sel = mode_arr[keep] == m
        L, P = true[keep][sel], pred[sel]
        info[m] = {
            "n_steps": int(sel.sum()),
            "n_detected": int((mode_arr == m).sum()),
            "n_recordings": int(len({str(r).split("#")[0] for r in recs[mode_arr == m]})),  # stretches of one recording count once
            "mean_true_length_m": float(L.mean()),
            "rms_residual_m": float(np.sqrt(np.mean((P - L) ** 2))),
            "fitted_over_true_total": float(P.sum() / L.sum()),
            "fitted_range": _fitted_range(feats[keep].reset_index(drop=True)[sel], m),
        }
    model.calibration_ = {"source": "truth trajectory", "modes": info}
    return model


def _fitted_range(feats: pd.DataFrame, mode: str) -> dict:
    """The band of a mode's fitted inputs (:data:`gaitml.pdr.step_length.FIT_RANGE_PERCENTILES`): what
    :meth:`StepLengthModel.outside_fit` checks a step against."""
    from gaitml.pdr.step_length import FIT_RANGE_PERCENTILES, WEINBERG_MODES

    cols = (
        {"range_ms2": (feats["a_max_ms2"] - feats["a_min_ms2"]).to_numpy(float)}
        if mode in WEINBERG_MODES
        else {
            "freq_hz": feats["freq_hz"].to_numpy(float),
            "var_ms2sq": feats["var_ms2sq"].to_numpy(float),
        }
    )
    return {k: [float(v) for v in np.percentile(x, FIT_RANGE_PERCENTILES)] for k, x in cols.items()}


def calibrate_from_truth(
    recordings,
    modes="walk",
    *,
    truths="self",
    detector=DEFAULT_STEP_DETECTOR,
    min_steps: int = MIN_CALIBRATION_STEPS,
    cutoff_hz: float = BODY_CUTOFF_HZ,
) -> StepLengthModel:
    """Fit the step length model per mode on several recordings that carry a truth trajectory.

    Parameters
    ----------
    recordings : sequence of Recording (a recording read in segments: every segment, each with its truth).
    modes : one mode for all (:data:`CALIBRATION_MODES`) or a list, one per recording. With ``labels``, every
        motion mode of the labels with at least ``min_steps`` steps is fitted; the other labels' steps (too few, or
        not a motion mode, e.g. standing) are left out and listed in ``calibration_['labels_left_out']``.
    truths : ``'self'`` / a file / ``(t_s, xy)`` for all, or a list, one per recording (:func:`truth_track`).
    detector : the step detector the PDR will use.
    min_steps, cutoff_hz : see :func:`fit_step_lengths` and :func:`step_length_samples`.

    Returns
    -------
    StepLengthModel (fitted as :func:`fit_step_lengths`; ``calibration_`` also names the detector).
    """
    recs = list(recordings)
    if not recs:
        raise InputError("no calibration recordings given; pass at least one recording with a truth trajectory.")
    mode_list = _per_recording(modes, len(recs), "modes")
    truth_list = _per_recording(truths, len(recs), "truths")
    parts = [
        step_length_samples(r, m, truth=t, detector=detector, cutoff_hz=cutoff_hz)
        for r, m, t in zip(recs, mode_list, truth_list, strict=True)
    ]
    samples = pd.concat(parts, ignore_index=True)
    given = {m for m in mode_list if m != "labels"}
    skipped = {}
    if "labels" in mode_list:  # a label's mode is fitted where it has enough steps; other labels (e.g. standing) are left out
        from_labels = np.concatenate([np.full(len(p), m == "labels") for p, m in zip(parts, mode_list, strict=True)])
        labelled = samples[from_labels & np.isfinite(samples["true_length_m"].to_numpy(float))]
        counts = labelled["mode"].value_counts()
        for m in sorted(set(samples.loc[from_labels, "mode"]) - given):
            if m in MOTION_MODES and counts.get(m, 0) >= min_steps:
                given.add(m)
            else:
                skipped[m] = int(counts.get(m, 0))
        samples = samples[~(from_labels & samples["mode"].isin(list(skipped)).to_numpy())].reset_index(drop=True)
        if not given:
            raise InputError(
                f"no labelled mode has {min_steps} steps with a true length (labels found: {skipped}); give the recordings' "
                "modes (--mode walk or run) or use longer recordings."
            )
    model = fit_step_lengths(samples, modes=sorted(given), min_steps=min_steps)
    model.calibration_.update(
        {"detector": detector if isinstance(detector, str) else type(detector).__name__, "body_cutoff_hz": float(cutoff_hz)}
    )
    if skipped:
        model.calibration_["labels_left_out"] = skipped  # label -> steps with a true length (too few, or not a motion mode)
    return model


def _per_recording(value, n: int, what: str) -> list:
    """``value`` for each of ``n`` recordings: a single value repeated or a list of ``n``."""
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(f"`{what}` must be one value or one per recording ({n}), got {len(value)}.")
        return list(value)
    return [value] * n


def main(argv: list[str] | None = None) -> int:
    """``python -m gaitml.pdr.calibrate INPUT [INPUT ...] --out STEP_LENGTH.json [--truth T ...] [--mode M ...] [--distance-m D]``.

    - ``--truth self|FILE`` (once for every input, or once per input): fit per mode on the
      inputs' truth trajectories (:func:`calibrate_from_truth`): a tyrex recording's motion
      capture (``self``, or its Qualisys CSV), a simulated recording's reference path
      (``self``), or a dense ``t,x_m,y_m`` CSV on the input's clock (as ``gaitml pdr --truth``).
      ``--mode`` (once, or once per input; default ``walk``) says what the steps of each input
      are: ``walk`` (eq. 12), ``run`` (eq. 13), ``backward``, ``side_left``, ``side_right``, or
      ``labels`` (the input's own labels). With a motion capture or a truth file, an input is read in
      segments (a sensor gap splits it; no step pair spans the gap); a reference path travels with a
      whole read only (a gap there is refused with the reader's message).
    - ``--distance-m D``: scale the defaults so that INPUT (one walk, every step ``--mode``) sums to D.
    - neither: fit per mode on INPUT's reference steps (one simulated or surveyed recording).

    The JSON is what ``gaitml pdr --step-length`` reads. Exit 2 with one error line on bad input.
    """
    import argparse
    import sys

    from gaitml.errors import GaitmlError
    from gaitml.io import FORMATS, read_recording, read_segments

    p = argparse.ArgumentParser(prog="python -m gaitml.pdr.calibrate", description="Calibrate the PDR step length model.")
    p.add_argument("inputs", metavar="INPUT", nargs="+", help="recording file(s) or folder(s)")
    p.add_argument("--out", metavar="JSON", required=True)
    p.add_argument(
        "--truth",
        metavar="T",
        action="append",
        help="truth trajectory: 'self' (the input's motion capture or reference path) or a dense t,x_m,y_m CSV / tyrex "
        "motion-capture CSV; once for all inputs or once per input",
    )
    p.add_argument(
        "--mode",
        action="append",
        choices=CALIBRATION_MODES,
        help="what each input's steps are (default walk); once for all inputs or once per input",
    )
    p.add_argument("--distance-m", type=float, help="known distance of one walk (scale calibration)")
    p.add_argument("--format", choices=FORMATS, help="input format (default: detected from the content)")
    p.add_argument(
        "--min-steps",
        type=int,
        default=MIN_CALIBRATION_STEPS,
        help=f"fewest steps with a true length per mode (default {MIN_CALIBRATION_STEPS})",
    )
    p.add_argument(
        "--detector",
        default=DEFAULT_STEP_DETECTOR,
        help=f"step detector (default {DEFAULT_STEP_DETECTOR}, as gaitml pdr's: calibrate with the detector you dead-reckon with)",
    )
    args = p.parse_args(argv)
    try:
        model = _run_cli(args, read_recording, read_segments)
        model.save(args.out)
    except GaitmlError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


def _per_input(values, n: int, flag: str, default):
    """A repeated option's values for ``n`` inputs: none (the default for all), one for all, or one each."""
    if not values:
        return [default] * n
    if len(values) == 1:
        return values * n
    if len(values) != n:
        raise InputError(f"{flag} is given {len(values)} times for {n} inputs; give it once for all inputs or once per input.")
    return list(values)


def _run_cli(args, read_recording, read_segments) -> StepLengthModel:
    """The work of :func:`main` (its arguments checked before any reading); the model to save."""
    import sys

    from gaitml.io import detect_format
    from gaitml.io._common import require_file
    from gaitml.pdr.step_length import WEINBERG_MODES
    from gaitml.steps import get_detector

    n = len(args.inputs)
    get_detector(args.detector)  # an unknown name fails here, before any reading
    if args.min_steps < 3:
        raise InputError(f"--min-steps must be >= 3 (eq. 12 has three coefficients), got {args.min_steps}.")
    if args.distance_m is not None and args.truth:
        raise InputError("--distance-m and --truth are two kinds of calibration; give one of them.")
    if not args.truth:
        if n > 1:
            raise InputError(
                f"{n} inputs without --truth: several inputs are fitted on their truth trajectories; pass --truth self "
                "(motion capture or a reference path) or --truth FILE."
            )
        if args.mode and args.distance_m is None:
            raise InputError("--mode names the steps of an input fitted on its truth; add --truth self|FILE, or drop --mode.")
        rec = read_recording(args.inputs[0], format=args.format)
        if args.distance_m is not None:
            mode = (args.mode or ["walk"])[0]
            if mode == "labels":
                raise InputError("--distance-m scales one mode; give --mode walk (or run, ...), not labels.")
            model = calibrate_walk_distance(rec, args.distance_m, detector=args.detector, mode=mode)
            print(f"scaled the {mode} model by {model.scale_:.4f} to {args.distance_m} m", file=sys.stderr)
            return model
        if rec.reference.get("steps") is None and (rec.reference.get("trajectory") is not None or rec.meta.get("format") == "tyrex"):
            raise InputError(f"{rec.name} has no true step events; fit on its truth trajectory with --truth self (and --mode walk|run).")
        cal = calibrate_from_reference(rec, detector=args.detector)
        print(f"fitted modes {cal.step_length.fitted_modes_} on {cal.n_matched} of {cal.n_detected} detected steps", file=sys.stderr)
        return cal.step_length
    truths = _per_input(args.truth, n, "--truth", "self")
    modes = _per_input(args.mode, n, "--mode", "walk")
    recs, rec_modes, rec_truths = [], [], []
    for path, mode, truth in zip(args.inputs, modes, truths, strict=True):
        # a truth outside the recording (motion capture, a truth file) is read on the original clock, so every
        # stretch between sensor gaps is used; a reference path travels only with a whole read
        whole = truth == "self" and (args.format or detect_format(require_file(path))) != "tyrex"
        segs = [read_recording(path, format=args.format)] if whole else read_segments(path, format=args.format)
        if len(segs) > 1:
            short = [g for g in segs if g.duration_s < MIN_SEGMENT_S]
            segs = [g for g in segs if g.duration_s >= MIN_SEGMENT_S]
            if short:
                print(
                    f"note: {Path(path).name}: {len(short)} stretch(es) between sensor gaps shorter than {MIN_SEGMENT_S:g} s left out "
                    f"({sum(g.duration_s for g in short):.1f} s); {len(segs)} used",
                    file=sys.stderr,
                )
        recs += segs
        rec_modes += [mode] * len(segs)
        rec_truths += [truth] * len(segs)
    model = calibrate_from_truth(recs, rec_modes, truths=rec_truths, detector=args.detector, min_steps=args.min_steps)
    if model.calibration_.get("labels_left_out"):
        print(f"note: labelled steps left out (label: steps with a true length): {model.calibration_['labels_left_out']}", file=sys.stderr)
    model.calibration_["inputs"] = [
        {"input": str(p), "mode": m, "truth": str(t)} for p, m, t in zip(args.inputs, modes, truths, strict=True)
    ]
    for m, d in model.calibration_["modes"].items():
        kind, params = model.coefficients_[m]
        eq = f"K {params[0]:.4f}" if m in WEINBERG_MODES else f"A {params[0]:.4f} m, B {params[1]:.4f} m s, C {params[2]:.5f}"
        print(
            f"{m}: {kind} ({eq}) from {d['n_steps']} of {d['n_detected']} detected steps in {d['n_recordings']} recording(s); "
            f"mean true step {d['mean_true_length_m']:.3f} m, RMS residual {d['rms_residual_m']:.3f} m, "
            f"fitted / true distance {d['fitted_over_true_total']:.3f} on these steps",
            file=sys.stderr,
        )
    return model


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
