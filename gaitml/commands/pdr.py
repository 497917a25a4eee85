"""`gaitml pdr INPUT [--model MODEL_DIR] [--out FILE] [--plot PNG] [--json]` (DESIGN sec. 5).

Contract: every argument is checked before any work; notes are printed only once the
dead reckoning has succeeded (a failing command prints its single error line); the
trajectory CSV and the plot are rendered to temporary files beside their targets and
renamed only at the end, so a failure leaves neither.
"""

from __future__ import annotations

import argparse
import contextlib
import os
from pathlib import Path

import numpy as np

from gaitml.commands._args import (
    add_input_options,
    choices,
    gyro_bias_modes,
    heading_sources,
    mode_assignments,
    mode_sources,
    step_detectors,
)
from gaitml.commands._util import (
    emit_json,
    gait_check_note,
    is_large_input,
    load_input,
    log,
    long_read_kwargs,
    rate_check_note,
    rate_check_summary,
)
from gaitml.commands.predict import add_run_cadence_option, run_cadence_arg
from gaitml.consts import DEFAULT_STEP_DETECTOR, SHORT_RUN_DEFAULT
from gaitml.errors import InputError

#: The command's one-line description in ``gaitml --help``.
HELP = "pedestrian dead reckoning trajectory"
#: What ``--gyro-bias-from`` does with the bias it reads when ``--gyro-bias`` is not given: ``'still'``
#: holds it for the whole walk (the attitude's ``start_bias`` with ``gyro_bias='still'``), ``'auto'``
#: starts from it and tracks it online as the default tracks. Chosen on the tyrex benchmark by the rule
#: written before measuring in experiments/reports/tyrex-pdr.md (section "A gyroscope bias from a still
#: recording", branch gyrocal; the figures are there).
GYRO_BIAS_FROM_MODE = "auto"
#: A still recording made at a sampling rate this far (relative) from the walk's is flagged: a phone's
#: gyroscope may run another filter (and bias) at another rate, or it may be another phone.
GYRO_BIAS_RATE_TOL = 0.10


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml pdr`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--model", metavar="MODEL_DIR")
    p.add_argument("--out", metavar="FILE")
    p.add_argument("--plot", metavar="PNG")
    p.add_argument("--json", action="store_true")
    p.add_argument(
        "--heading", **choices("pdr", "--heading", heading_sources), default="hde", help="heading source: %(choices)s (default hde)"
    )
    p.add_argument(
        "--modes",
        **choices("pdr", "--modes", mode_sources),
        help="motion modes per step: %(choices)s (default: model with --model, else the labels, else forward)",
    )
    p.add_argument(
        "--mode-boundaries",
        **choices("pdr", "--mode-boundaries", mode_assignments),
        default="auto",
        help="with --model: re-place each mode change at the most likely step (refine) or keep the nearest window's mode (nearest), "
        "or take the window nearest the middle of each step (middle); auto (default) refines when steps are timed by their peaks",
    )
    p.add_argument(
        "--detector",
        **choices("pdr", "--detector", step_detectors),
        default=None,
        help=f"step detector: %(choices)s (default {DEFAULT_STEP_DETECTOR}, or a step-window model's own detector; "
        "single-peak is paper 003's)",
    )
    p.add_argument("--step-length", metavar="JSON", help="calibrated step length model (StepLengthModel.save)")
    add_run_cadence_option(p)
    p.add_argument(
        "--short-runs",
        type=_short_runs_arg,
        default=None,
        metavar="WINDOWS",
        help="with --model: a run of side or backward steps between forward steps holding fewer steps than this many model "
        "windows (at the walker's median step interval; paper 003 sec. 3.4 at the step level) moves forward; 0 keeps "
        f"every run (default {SHORT_RUN_DEFAULT:g})",
    )
    p.add_argument(
        "--gyro-bias",
        **choices("pdr", "--gyro-bias", gyro_bias_modes),
        default=None,
        help="gyroscope bias removed before the heading: from still stretches, then tracked while the tilt is steady (auto, "
        "default), from still stretches only (still), or none (off, paper 003 as written); with --gyro-bias-from: "
        f"hold that bias (still) or track it from there (auto); default {GYRO_BIAS_FROM_MODE}",
    )
    p.add_argument(
        "--gyro-bias-from",
        metavar="STILL",
        help="take the gyroscope bias from STILL, a recording of the same phone lying still (any input format, read with "
        "the input options; the mean rate over its still stretches, >= 5 s) or a JSON written by gaitml pdr --json "
        "(its gyro_bias record), instead of the walk's own still stretches",
    )
    p.add_argument(
        "--hde-guard",
        choices=("on", "off"),
        default="on",
        help="with an HDE heading: apply HDE only when the step headings line up with dominant directions above chance, "
        "else keep the uncorrected heading and say so (on, default); off applies HDE always (paper 003 as written)",
    )
    p.add_argument(
        "--initial-heading-rad",
        type=float,
        default=None,
        help="compass heading at the start (default: the reference trajectory's when the input has one, else 0 = north)",
    )
    p.add_argument(
        "--truth",
        metavar="FILE",
        help="score against landmarks or a reference path: a GetSensorData log (its POSI lines), a CSV t,x_m,y_m[,floor] / "
        "t,x_mm,y_mm / t,lat,lon[,floor] on the input's clock, or 'self' for the input's own landmarks or reference trajectory",
    )
    p.add_argument(
        "--truth-align",
        choices=("start-heading", "start", "none"),
        default="start-heading",
        help="align the trajectory on the truth's start position and initial heading (default), the start position only, or not at all",
    )
    p.add_argument(
        "--truth-heading-m",
        type=float,
        default=5.0,
        help="with --truth-align start-heading: the heading is taken to the first truth point this far along the truth (default 5 m)",
    )
    add_input_options(p)


def _short_runs_arg(text: str) -> float:
    """``--short-runs``: a finite number of model windows >= 0 (argparse reports a bad one in one line)."""
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not (np.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"must be a number of model windows >= 0 (0: off), got {text!r}")
    return v


def check_output_path(path: str, flag: str) -> Path:
    """Raise InputError when ``path`` cannot be written as a file (checked before any work)."""
    p = Path(path)
    if p.is_dir():
        raise InputError(f"{flag} {path} is a directory; pass a file path.")
    for parent in p.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"cannot write {flag} {path}: {parent} is a file, not a folder; choose another output path.")
            if not os.access(parent, os.W_OK | os.X_OK):
                raise InputError(f"cannot write {flag} {path}: folder {parent} is not writable; choose another output path.")
            break
    return p


def _validate(args) -> None:
    out = check_output_path(args.out, "--out") if args.out else None
    plot = check_output_path(args.plot, "--plot") if args.plot else None
    if out is not None and plot is not None and out.resolve() == plot.resolve():
        raise InputError(f"--out and --plot are the same file {args.out}; give them different paths.")
    if getattr(args, "truth", None) and args.truth != "self":
        from gaitml.io._common import require_file

        require_file(args.truth)
    if getattr(args, "truth_heading_m", 5.0) is not None and not getattr(args, "truth_heading_m", 5.0) > 0:
        raise InputError(f"--truth-heading-m must be > 0 m, got {args.truth_heading_m}.")
    if getattr(args, "modes", None) == "model" and not args.model:
        raise InputError("--modes model needs a model; pass --model MODEL_DIR, or use --modes true (labels) or --modes forward.")
    if getattr(args, "gyro_bias_from", None):
        from gaitml.io._common import require_file

        if getattr(args, "gyro_bias", None) == "off":
            raise InputError("--gyro-bias off removes no bias, so --gyro-bias-from has nothing to do; drop one of them.")
        if not Path(args.gyro_bias_from).is_dir():
            require_file(args.gyro_bias_from)


def _gyro_bias_args(args, notes: list[str]) -> dict:
    """``run_pdr`` / ``long_pdr`` keywords of ``--gyro-bias`` and ``--gyro-bias-from``: the mode and the bias
    measured elsewhere (:func:`gaitml.signal.gyro_bias_from_still` of a still recording read with the input
    options, or :func:`gaitml.signal.read_gyro_bias_json`), or None."""
    mode = getattr(args, "gyro_bias", None)
    path = getattr(args, "gyro_bias_from", None)
    if not path:
        return {"gyro_bias": mode or "auto"}
    from gaitml.signal import gyro_bias_from_still, read_gyro_bias_json

    if Path(path).is_file() and Path(path).suffix.lower() == ".json":
        start = read_gyro_bias_json(path)
    else:
        from gaitml.commands._util import read_kwargs
        from gaitml.io import read_recording

        still = read_recording(path, **read_kwargs(args))
        start = gyro_bias_from_still(still, source=str(path))
        start.params["sampling_rate_hz"] = _made_at_hz(still)
    mode = mode or GYRO_BIAS_FROM_MODE
    notes.append(
        f"gyroscope bias from {path} ({start.method}), "
        + ("held for the whole walk (--gyro-bias still)" if mode == "still" else "then tracked online (--gyro-bias auto)")
    )
    return {"gyro_bias": mode, "gyro_bias_start": start}


def _made_at_hz(rec) -> float | None:
    """The rate a recording (or a chunked reader's scan) was made at: the rate its reader judged its timestamps at
    (``meta['original_rate_hz']``) before the input options resampled it (``--sampling-rate-hz``), else its rate."""
    if rec is None:
        return None
    made = (getattr(rec, "meta", None) or {}).get("original_rate_hz")
    try:
        made = float(made)
    except (TypeError, ValueError):
        made = None
    return made if made is not None and made > 0 else float(rec.sampling_rate_hz)


def _warn_still_rate(gb_args: dict, walk_rate_hz: float | None, res) -> None:
    """One warning line when the still recording was made at a sampling rate other than the walk's
    (:data:`GYRO_BIAS_RATE_TOL`; both as made, :func:`_made_at_hz`, not as resampled to one rate by the input
    options); the line is also kept in the JSON's ``gyro_bias`` record (``still_rate_warning``) and the summary."""
    start = gb_args.get("gyro_bias_start")
    still_hz = None if start is None else start.params.get("sampling_rate_hz")
    if still_hz is None or not walk_rate_hz:
        return
    if abs(still_hz - walk_rate_hz) > GYRO_BIAS_RATE_TOL * walk_rate_hz:
        line = (
            f"the still recording {start.source} was made at {still_hz:.1f} Hz and the walk at {walk_rate_hz:.1f} Hz: "
            "a gyroscope's bias can change with its rate setting, or it is another phone; record it at the walk's rate"
        )
        log(f"gaitml: warning: {line}")
        if isinstance(res.info.get("gyro_bias"), dict):
            res.info["gyro_bias"]["still_rate_warning"] = line


def _detector(args, model, notes: list[str]) -> str:
    """The step detector: --detector, else a step-window model's own detector, else :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`.

    A model trained on step windows (model.json ``window.by = "steps"``) classifies the
    PDR's steps directly; by default they come from the detector it was trained with.
    """
    given = getattr(args, "detector", None)
    if given:
        return given
    if model is not None and model.window_by == "steps":
        notes.append(f"steps from the step-window model's detector {model.window_detector} (pass --detector to choose another)")
        return model.window_detector
    return DEFAULT_STEP_DETECTOR


def _hde(args, h0: float, notes: list[str]):
    """The HDE of ``--hde-guard off`` (its structure guard off), or None: the default HDE, guard on.
    With a heading without HDE (``gyro``, ``dwpca``) ``--hde-guard off`` changes nothing, and a note says so."""
    if getattr(args, "hde_guard", "on") != "off":
        return None
    heading = getattr(args, "heading", "hde")
    if heading not in ("hde", "dwpca-hde"):
        notes.append(f"--hde-guard off has no effect with --heading {heading} (no HDE); it applies to --heading hde and dwpca-hde.")
        return None
    from gaitml.pdr.hde import HeuristicDriftElimination

    return HeuristicDriftElimination(reference_rad=h0, structure_alpha=None)


def _kept_heading(heading: str) -> tuple[str, str]:
    """What an HDE heading source keeps when HDE is held off, and the option that asks for it."""
    return ("DW-PCA", "--heading dwpca") if heading == "dwpca-hde" else ("gyro", "--heading gyro")


def _heading_check_line(res) -> str | None:
    """The text summary's line on HDE's structure guard (:func:`gaitml.pdr.hde.hde_heading`), or None without HDE."""
    check = res.info.get("heading_check")
    if not check:
        return None
    n, mn = check["n_steps"], check["min_steps"]
    if check["statistic"] is None:
        evidence = f"{n} step" if n == 1 else f"{n} steps"
    else:
        rel = ">" if check["statistic"] > check["threshold"] else "<="
        evidence = f"alignment {check['statistic']:.3f} {rel} chance threshold {check['threshold']:.3f} over {n} steps"
    if check["guard"] == "off":
        shape = "dominant directions" if check["structured"] else "no dominant directions"
        return f"heading check: guard off, HDE applied ({shape}: {evidence})"
    if check["hde_applied"]:
        return f"heading check: HDE applied (dominant directions: {evidence})"
    kept = _kept_heading(str(res.info.get("heading")))[0]
    why = f"fewer than {mn} steps" if check["reason"] == "too few steps" else "no dominant directions"
    return f"heading check: HDE not applied, {kept} heading kept ({why}: {evidence})"


def _warn_heading_check(res) -> None:
    """One warning line when HDE's structure guard held HDE off (the recording lies outside HDE's premise)."""
    check = res.info.get("heading_check")
    if not check or check["hde_applied"]:
        return
    kept, option = _kept_heading(str(res.info.get("heading")))
    if check["reason"] == "too few steps":
        n = check["n_steps"]
        why = f"only {n} step{'' if n == 1 else 's'}, fewer than the {check['min_steps']} it needs to test its premise (walking along dominant directions)"
    else:
        why = (
            f"the step headings show no dominant directions (alignment {check['statistic']:.3f} <= chance threshold "
            f"{check['threshold']:.3f} over {check['n_steps']} steps): HDE assumes a walk along a building's main directions, "
            "and a walk that loops or wanders lies outside it"
        )
    log(
        f"gaitml: warning: HDE not applied, the uncorrected {kept} heading is kept: {why}; pass {option} to ask for that "
        "heading, or --hde-guard off to force HDE"
    )


def run(args) -> int:
    """Dead-reckon INPUT; print a summary or the JSON contract; optionally write the table and a plot."""
    from gaitml.io import atomic_path
    from gaitml.pdr import run_pdr
    from gaitml.pdr.step_length import StepLengthModel

    _validate(args)
    notes: list[str] = []
    model = None
    if args.model:
        from gaitml.models import load_model

        model = load_model(args.model)
    step_length = StepLengthModel.load(args.step_length) if getattr(args, "step_length", None) else None
    if is_large_input(args):
        return _run_long(args, model, step_length, notes)
    rec = load_input(args)
    rec.require_gyr("PDR heading")
    modes = getattr(args, "modes", None)
    if modes is None:
        if model is not None:
            modes = "model"
        elif rec.labels is not None:
            modes = "true"
            notes.append("no --model; using the recording's own per-sample labels as the motion modes (--modes true).")
        else:
            modes = "forward"
            notes.append("no --model and no labels: every step is treated as a forward walk step (traditional PDR, --modes forward).")
    if modes == "true" and rec.labels is None:
        raise InputError(f"--modes true needs per-sample labels but {rec.name} has none; pass --model MODEL_DIR or use --modes forward.")
    if step_length is None:
        notes.append("step lengths from the uncalibrated default model (pass --step-length FILE.json for a calibrated one).")
    h0 = getattr(args, "initial_heading_rad", None)
    truth = rec.reference.get("trajectory")
    if h0 is None:
        if truth is not None and len(truth) and "heading_rad" in truth:
            h0 = float(truth["heading_rad"].iloc[0])
            notes.append(
                f"start heading {h0:.3f} rad taken from the input's reference trajectory (no compass; pass --initial-heading-rad to override)."
            )
        else:
            h0 = 0.0
    truth_obj = _load_truth(args, rec)
    detector = _detector(args, model, notes)
    gb_args = _gyro_bias_args(args, notes)
    res = run_pdr(
        rec,
        model=model,
        detector=detector,
        heading=getattr(args, "heading", "hde"),
        modes=modes,
        mode_boundaries=getattr(args, "mode_boundaries", "auto"),
        step_length=step_length,
        initial_heading_rad=h0,
        **gb_args,
        run_min_cadence_hz=run_cadence_arg(getattr(args, "run_cadence", None)),
        hde=_hde(args, h0, notes),
        short_run_windows=getattr(args, "short_runs", None),
    )
    notes += list(res.info["notes"])
    scored = _score(args, rec, res, truth_obj) if truth_obj is not None else None
    # Both outputs are rendered to temporary files beside their targets; they are renamed
    # only when both are complete (a failure removes both temporaries).
    with contextlib.ExitStack() as stack:
        if args.plot and scored is not None:
            from gaitml.pdr.plot_truth import plot_truth_score

            tmp_plot = stack.enter_context(atomic_path(args.plot, suffix=".png"))
            sm = scored["summary"]
            title = (
                f"{rec.name} vs {truth_obj.source} ({truth_obj.kind}, align {sm['align']})\nmean {sm['mean_error_m']:.2f} m, "
                f"p75 {sm['p75_error_m']:.2f} m, end {sm['end_error_m']:.2f} m = {sm.get('end_error_pct_distance', float('nan')):.2f} % of {sm['distance_m']:.0f} m"
            )
            plot_truth_score(
                tmp_plot, scored["aligned_xy"], scored["points"], truth_obj.table, dense=truth_obj.kind == "dense", title=title
            )
        elif args.plot:
            from gaitml.pdr.plot import plot_trajectory

            tmp_plot = stack.enter_context(atomic_path(args.plot, suffix=".png"))
            title = (
                f"{rec.name}: {res.n_steps} steps, heading {res.info['heading']}, modes {res.info['modes']}, update {res.info['update']}"
            )
            plot_trajectory(tmp_plot, res.trajectory, truth=truth, title=title)
        if args.out:
            tmp_out = stack.enter_context(atomic_path(args.out, suffix=".csv"))
            res.trajectory.to_csv(tmp_out, index=False)
    for note in notes:
        log(f"note: {note}")
    gait_check_note(res.info.get("gait_check"), detector)
    rate_check_note(res.info.get("rate_check"))  # below the step detector's rate floor (gaitml.steps._rate)
    _warn_heading_check(res)
    _warn_out_of_domain(model, modes, res.steps)
    _warn_outside_fit(res)
    _warn_calibration_detector(res)
    _warn_still_rate(gb_args, _made_at_hz(rec), res)
    # ---- a fixed-threshold detector that misses calm steps or counts a bouncing phone's extra peaks
    # (gaitml.steps.crosscheck): one warning line
    from gaitml.steps.crosscheck import count_warning

    count_msg = count_warning(rec, res.n_steps, detector)
    if count_msg:
        log(f"gaitml: warning: {count_msg}")
    extra_json = {"truth": _truth_json(truth_obj, scored)} if scored is not None else {}
    extra_lines = _truth_lines(truth_obj, scored) if scored is not None else []
    return _report(args, res, rec.name, res.info["modes"], truth, count_msg, extra_json, extra_lines)


def _run_long(args, model, step_length, notes: list[str]) -> int:
    """A long input (over :data:`gaitml.io.chunked.LARGE_INPUT_SAMPLES`): dead reckoning chunk by chunk
    (:func:`gaitml.chunked_run.long_pdr`, bounded memory), the same outputs as a file read whole
    (the start heading and the end-point line from a gaitml-csv's reference trajectory sidecar too).

    ``--truth`` is refused (it scores against the whole recording held in memory); the plot shows the
    per-step trajectory (one point per step).
    """
    from gaitml.chunked_run import check_long_pdr, long_pdr
    from gaitml.io import atomic_path
    from gaitml.steps.crosscheck import CROSSCHECK_DETECTOR, FIXED_THRESHOLD_DETECTORS, compare_counts

    name = Path(args.input).name
    if getattr(args, "truth", None):
        raise InputError(
            f"--truth scores against the whole recording in memory and {name} is read in chunks (a long file); "
            "score a shorter part (gaitml split) or run without --truth."
        )
    check_long_pdr(
        args.input,
        getattr(args, "heading", "hde"),
        model=model,
        modes=getattr(args, "modes", None),
        mode_boundaries=getattr(args, "mode_boundaries", "auto"),
    )
    detector = _detector(args, model, notes)
    gb_args = _gyro_bias_args(args, notes)
    also = CROSSCHECK_DETECTOR if detector in FIXED_THRESHOLD_DETECTORS and detector != CROSSCHECK_DETECTOR else None
    truth = _long_reference(args)
    h0 = getattr(args, "initial_heading_rad", None)
    if h0 is None and truth is not None and len(truth) and "heading_rad" in truth:
        h0 = float(truth["heading_rad"].iloc[0])
        notes.append(
            f"start heading {h0:.3f} rad taken from the input's reference trajectory (no compass; pass --initial-heading-rad to override)."
        )
    read_kw = long_read_kwargs(args)
    first = read_kw.get("scan") or read_kw.get("recording")
    res = long_pdr(
        args.input,
        model=model,
        detector=detector,
        heading=getattr(args, "heading", "hde"),
        modes=getattr(args, "modes", None),
        mode_boundaries=getattr(args, "mode_boundaries", "auto"),
        step_length=step_length,
        initial_heading_rad=0.0 if h0 is None else h0,
        count_also=also,
        run_min_cadence_hz=run_cadence_arg(getattr(args, "run_cadence", None)),
        short_run_windows=getattr(args, "short_runs", None),
        progress=True,
        **gb_args,
        hde=_hde(args, 0.0 if h0 is None else h0, notes),
        **read_kw,
    )
    modes = res.info["modes"]
    name = res.steps.attrs.get("recording_name", name)
    if step_length is None:
        notes.append("step lengths from the uncalibrated default model (pass --step-length FILE.json for a calibrated one).")
    notes.insert(0, f"{name} is long: read in chunks (bounded memory); the heading is integrated across the chunks")
    notes += list(res.info["notes"])
    with contextlib.ExitStack() as stack:
        if args.plot:
            from gaitml.pdr.plot import plot_trajectory

            tmp_plot = stack.enter_context(atomic_path(args.plot, suffix=".png"))
            title = f"{name}: {res.n_steps} steps, heading {res.info['heading']}, modes {modes}, update {res.info['update']}"
            plot_trajectory(tmp_plot, res.trajectory, truth=truth, title=title)
        if args.out:
            tmp_out = stack.enter_context(atomic_path(args.out, suffix=".csv"))
            res.trajectory.to_csv(tmp_out, index=False)
    for note in notes:
        log(f"note: {note}")
    gait_check_note(res.info.get("gait_check"), detector)
    rate_check_note(res.info.get("rate_check"))  # below the step detector's rate floor (gaitml.steps._rate)
    _warn_heading_check(res)
    _warn_out_of_domain(model, modes, res.steps)
    _warn_outside_fit(res)
    _warn_calibration_detector(res)
    _warn_still_rate(gb_args, _made_at_hz(first), res)
    count_msg = compare_counts(res.n_steps, res.steps.attrs["count_also"]["n_steps"], detector) if also else None
    if count_msg:
        log(f"gaitml: warning: {count_msg}")
    return _report(args, res, name, modes, truth, count_msg)


def _long_reference(args):
    """The reference trajectory of a long gaitml-csv input (its ``<stem>.trajectory.csv`` sidecar, read as a
    whole-file read reads it), or None."""
    from gaitml.io._detect import detect_format
    from gaitml.io.gaitml_csv import _read_sidecars

    p = Path(args.input)
    if getattr(args, "columns", None) is not None or (getattr(args, "format", None) or detect_format(p)) != "gaitml-csv":
        return None
    return _read_sidecars(p).get("trajectory")


def _reference_lines(res, truth) -> list[str]:
    """The summary line comparing the end point with the input's reference trajectory (none without one)."""
    from gaitml.evaluation.trajectory import end_point_error

    if truth is None or not len(truth):
        return []
    xy = truth[["x_m", "y_m"]].to_numpy(float)
    d_true = float(np.linalg.norm(np.diff(xy, axis=0), axis=1).sum())
    if not d_true > 0:
        return []
    err, pct = end_point_error(res.trajectory[["x_m", "y_m"]].to_numpy(), xy[-1], d_true)
    return [f"  truth: distance {d_true:.1f} m; end-point error {err:.2f} m = {pct:.2f} % of distance"]


# ---- scoring against ground truth: --truth, --truth-align, --truth-heading-m
def _load_truth(args, rec):
    """The truth of ``--truth`` on the recording's time base, or None; its notes go to stderr."""
    spec = getattr(args, "truth", None)
    if not spec:
        return None
    from gaitml.evaluation.trajectory import BODY_CUTOFF_HZ, body_track
    from gaitml.io.truth import recording_truth

    # a tyrex motion capture follows the walker, not the phone's arm swing (the other truths are used as they are)
    note = f"the phone's path low-passed at {BODY_CUTOFF_HZ:g} Hz to follow the walker (arm swing removed)"
    return recording_truth(rec, spec, smooth=body_track, smooth_note=note)


def _score(args, rec, res, truth) -> dict:
    from gaitml.evaluation.positioning import apply_alignment, score_positions

    traj = res.trajectory
    xy = traj[["x_m", "y_m"]].to_numpy(float)
    points, summary = score_positions(
        traj["t_s"].to_numpy(float),
        xy,
        truth.table,
        align=getattr(args, "truth_align", "start-heading"),
        heading_distance_m=getattr(args, "truth_heading_m", 5.0),
        t_end_s=rec.duration_s,
    )
    if summary["n_outside"]:
        truth.notes.append(
            f"{summary['n_outside']} truth point(s) lie outside the recording (0 to {rec.duration_s:.1f} s) and were not scored"
        )
    for note in truth.notes:
        log(f"note: truth: {note}")
    aligned = apply_alignment(xy, summary) if summary["align"] != "none" else xy
    return {"points": points, "summary": summary, "aligned_xy": aligned}


def _truth_json(truth, scored) -> dict:
    pts = scored["points"]
    records = []
    for r in pts.itertuples(index=False):
        d = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in r._asdict().items()}
        records.append(d)
    return {
        "source": truth.source,
        "kind": truth.kind,
        "notes": list(truth.notes),
        **scored["summary"],
        "points": records if truth.kind == "landmarks" else records[:: max(1, len(records) // 2000)],
        "points_every": 1 if truth.kind == "landmarks" else max(1, len(records) // 2000),
    }


def _truth_lines(truth, scored) -> list[str]:
    sm = scored["summary"]
    lines = [
        f"  truth {truth.source} ({truth.kind}, {len(truth.table)} points, align {sm['align']}, rotation {np.degrees(sm['rotation_rad']):.1f} deg): "
        f"{sm['n_points']} scored, mean {sm['mean_error_m']:.2f} m, p75 {sm['p75_error_m']:.2f} m, max {sm['max_error_m']:.2f} m, "
        f"end {sm['end_error_m']:.2f} m = {sm.get('end_error_pct_distance', float('nan')):.2f} % of {sm['distance_m']:.1f} m walked"
    ]
    for g in sm.get("segments", []):
        if g["n_points"]:
            lines.append(
                f"    segment {g['segment']} (floor {g['floor']:g}): {g['n_points']} points, mean {g['mean_error_m']:.2f} m, p75 {g['p75_error_m']:.2f} m"
            )
    if truth.kind == "landmarks":
        lines.append(f"    {'#':>3s} {'t_s':>8s} {'error_m':>8s} {'dist_m':>8s} {'err_%':>7s} {'floor':>5s}  role")
        for k, r in enumerate(scored["points"].itertuples(index=False)):
            pct = f"{r.error_pct_distance:7.2f}" if np.isfinite(r.error_pct_distance) else f"{'-':>7s}"
            fl = f"{r.floor:5g}" if np.isfinite(r.floor) else f"{'-':>5s}"
            lines.append(f"    {k:3d} {r.t_s:8.2f} {r.error_m:8.2f} {r.distance_m:8.1f} {pct} {fl}  {r.role}")
    return lines


def _warn_outside_fit(res) -> None:
    """One warning line when steps lie outside the inputs a calibrated step-length model was fitted on."""
    n_out = res.info.get("step_length_outside_fit")
    if not n_out:
        return
    per_mode = res.steps.loc[res.steps["step_length_outside_fit"].astype(bool), "mode"].astype(str).value_counts()
    which = ", ".join(f"{n} {m}" for m, n in per_mode.items())
    log(
        f"gaitml: warning: {n_out} of {res.n_steps} steps ({which}) lie outside the cadence / acceleration the step-length model "
        "was calibrated on, or are of a mode it was not calibrated for (the stated default length): their lengths are "
        "extrapolated; calibrate on recordings like this one (runs as --mode run with --model, or as --mode walk for "
        "forward-only dead reckoning)"
    )


def _warn_calibration_detector(res) -> None:
    """One warning line when the step-length calibration was fitted on another step detector's steps
    (:func:`gaitml.pdr.pipeline.calibration_detector_check`)."""
    check = res.info.get("step_length_detector")
    if not check:
        return
    cal, det = check["calibrated_with"], check["detector"]
    log(
        f"gaitml: warning: the step-length model was calibrated with {cal}'s steps and this run detects them with {det}: "
        f"its lengths carry {cal}'s missed and extra steps, so the distance may be off by the ratio of the two counts; "
        f"run with --detector {cal}, or calibrate with --detector {det}"
    )


def _warn_out_of_domain(model, modes: str, steps) -> None:
    """One warning line when model modes were used and steps lie outside the model's training domain."""
    if model is None or modes != "model":
        return
    from gaitml.commands._domain import domain_warning

    flags = steps["in_domain"].to_numpy(dtype=object) if "in_domain" in steps else []
    reasons = steps["out_of_domain_reason"].to_numpy(dtype=object) if "out_of_domain_reason" in steps else None
    warning = domain_warning(model, flags, what="steps", reasons=reasons)
    if warning:
        tail = "; they were moved forward along the facing heading" if model.domain is not None else ""
        log(f"gaitml: warning: {warning}{tail}")
    if "mode_model" in steps and "in_domain" in steps:
        side = steps["mode_model"].astype(str).str.startswith("side_") & (steps["mode"].astype(str) == "walk")
        n_unsure = int((side & steps["in_domain"].map(lambda v: v is True or v is np.True_)).sum())
        if n_unsure:
            log(
                f"gaitml: warning: {n_unsure} side steps of unsure direction (the phone's placement in a pocket or a swinging "
                "hand hides which way is left) were moved forward along the facing heading; use --modes true if you know them"
            )


def _report(args, res, name: str, modes: str, truth, count_msg: str | None, extra_json: dict | None = None, extra_lines=()) -> int:
    """The JSON object or the text summary of a PDR run (a file read whole or in chunks)."""
    if args.json:
        obj = res.to_json_dict()
        if count_msg:
            obj["warnings"] = [count_msg]
        obj.update(extra_json or {})
        emit_json(obj)
        return 0
    x, y = res.end_xy_m
    lines = [
        f"{name}: {res.n_steps} steps, distance {res.distance_m:.1f} m, end point ({x:.2f}, {y:.2f}) m "
        f"[heading {res.info['heading']}, modes {modes}, update {res.info['update']}]"
    ]
    if res.info.get("out_of_domain_steps") is not None:
        foot = res.info.get("foot_mounted_steps")
        foot_txt = f"; {foot} of them rest between fast swings (a foot-mounted sensor?)" if foot else ""
        lines.append(
            f"  out of the model's domain: {res.info['out_of_domain_steps']} of {res.n_steps} steps (moved forward along the facing heading{foot_txt})"
        )
    if res.info.get("side_direction_unsure_steps"):
        lines.append(
            f"  side steps of unsure direction: {res.info['side_direction_unsure_steps']} (moved forward along the facing heading)"
        )
    if res.info.get("gyro_bias"):
        lines.append(f"  {res.info['gyro_bias']['note']}")
        if res.info["gyro_bias"].get("still_rate_warning"):
            lines.append(f"  gyroscope bias: {res.info['gyro_bias']['still_rate_warning']}")
    check = _heading_check_line(res)
    if check:
        lines.append(f"  {check}")
    rate = rate_check_summary(res.info.get("rate_check"))  # the stderr warning's summary (gaitml.steps._rate)
    if rate:
        lines.append(f"  {rate}")
    if res.info.get("step_length_outside_fit"):
        lines.append(
            f"  step lengths extrapolated (outside the calibration's inputs or modes): {res.info['step_length_outside_fit']} of {res.n_steps} steps"
        )
    if res.info.get("step_length_detector"):
        check = res.info["step_length_detector"]
        lines.append(f"  step lengths calibrated with {check['calibrated_with']}, steps detected with {check['detector']}")
    lines.extend(_reference_lines(res, truth))
    lines.extend(extra_lines)
    if args.out:
        lines.append(f"  trajectory written to {args.out}")
    if args.plot:
        lines.append(f"  plot written to {args.plot}")
    print("\n".join(lines))
    return 0
