"""`gaitml steps INPUT [--detector NAME] [--out FILE] [--json] [--[no-]gait-check]` (DESIGN sec. 5).

With ``--gait-check`` (the default for ``adaptive``, the default detector; the paper detectors run as published unless asked) the steps pass the
gait-evidence test of :mod:`gaitml.steps._gait_evidence`: bouts whose phone
rotates at the step rate as a gesturing hand does are left out (needs a
gyroscope); the text, the JSON (``gait_check``) and one stderr line say how
many steps were left out. Other detectors' steps are tested at ``adaptive``'s
local cadence (its stride-versus-step decision).

For a detector that rates its steps (``adaptive``) the summary also says whether
its steps are confident gait (:func:`gaitml.steps.gait_confidence`: a bout of
at least ten regular steps within 60 s) or unsure: the text line "N steps, M
confident, K unsure", the JSON keys ``n_confident``, ``n_unsure``,
``gait_confidence`` and ``confident`` per step, and one stderr note when most
steps are unsure ("no confident gait found" when none is confident). Nothing is
dropped; the written step table gets a ``confident`` column. A long input read in
chunks gets the same verdict: it reads only the global step table.

A recording made below the lowest rate the detector's count holds at (its rate floor,
:mod:`gaitml.steps._rate`; the rate read before any up-sampling) is counted as always and
flagged: one stderr warning line naming the rate, the floor and the fix, ``rate_check`` in the
JSON (with ``rate_reason`` per step when a step is flagged), a ``rate_reason`` column in the
written table and a summary line. A stretch recorded below it (``meta['rate_changes']``) flags
the steps in it.
"""

from __future__ import annotations

import argparse

import numpy as np

from gaitml.commands._args import add_input_options, choices, step_detectors
from gaitml.commands._util import emit_json, is_large_input, load_input, log, long_read_kwargs, rate_check_note, rate_check_summary
from gaitml.consts import DEFAULT_STEP_DETECTOR

#: The stderr note of a recording in which the detector found no step.
NO_STEPS_NOTE = "note: no steps found; check the recording contains walking and the detector suits the sensor position."
#: The command's one-line description in ``gaitml --help``.
HELP = "detect steps"

#: detectors whose steps pass the gait-evidence test unless ``--no-gait-check``: on the tyrex walks and runs of the
#: two people the test was set on it cost them no steps; the FSM and autocorrelation detectors lost running steps
#: (experiments/reports/nongait.md), so for them it is opt-in (``--gait-check``)
GAIT_CHECK_BY_DEFAULT = ("adaptive",)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml steps`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--detector",
        **choices("steps", "--detector", step_detectors),
        default=DEFAULT_STEP_DETECTOR,
        help="%(choices)s (default %(default)s; single-peak is paper 003's)",
    )
    p.add_argument("--out", metavar="FILE", help="write the step table as CSV")
    p.add_argument("--json", action="store_true")
    p.add_argument(
        "--gait-check",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="leave out bouts of steps without gait evidence (a phone rotating at the step rate, as a gesturing hand "
        "does; needs a gyroscope). Default: on for adaptive, off for the paper detectors (run as published)",
    )
    add_input_options(p)


def _evaluation(rec, steps) -> dict | None:
    from gaitml.evaluation.steps import evaluate_steps

    ref = rec.reference
    true_s = ref.get("steps_t_s")
    n_true = ref.get("n_steps_true")
    if true_s is None and not n_true:
        return None
    if true_s is not None:
        true_s = np.asarray(true_s, dtype=float)
    return evaluate_steps(steps, true_s, n_true=int(n_true) if n_true else None)


#: optional step-table columns ``--json`` carries per step when the detector gives them
JSON_STEP_COLUMNS = ("cadence_hz", "confidence")


def _json_steps(steps, t) -> list[dict]:
    """One JSON object per step: ``t_s``, ``period_s`` and the optional columns the table has."""
    cols = {"period_s": steps["period_s"].to_numpy(dtype=float)}
    cols.update({c: steps[c].to_numpy(dtype=float) for c in JSON_STEP_COLUMNS if c in steps.columns})
    return [{"t_s": float(a), **{k: float(v[i]) for k, v in cols.items()}} for i, a in enumerate(np.asarray(t, dtype=float))]


def _json_cadence(cad) -> list[dict] | None:
    """The per-window cadence (a detector's ``cadence_``, or the chunked road's ``attrs["cadence"]``), if any."""
    if cad is None:
        return None
    return [
        {"t_s": float(r.t_s), "cadence_hz": float(r.cadence_hz), "periodicity": float(r.periodicity), "stride": bool(r.stride)}
        for r in cad.itertuples(index=False)
    ]


def _gait_line(checked: dict | None) -> str | None:
    """One line on the gait-evidence test (None when it was switched off)."""
    if checked is None:
        return None
    if not checked["tested"]:
        return "not run (the recording has no gyroscope); bouts without gait evidence cannot be told apart"
    n, m = checked["n_steps_rejected"], checked["n_bouts_rejected"]
    if not n:
        return f"every bout of steps shows gait evidence ({checked['n_bouts']} bouts)"
    return (
        f"{n} steps in {m} of {checked['n_bouts']} bouts without gait evidence left out (the phone rotates at the step rate "
        "as a gesturing hand does, not as a walker's); --no-gait-check keeps them"
    )


def _confidence(steps) -> tuple[dict | None, np.ndarray | None]:
    """The confident / unsure verdict (:func:`gaitml.steps.gait_confidence`) and the per-step flags, for detectors
    that rate their steps (a ``confidence`` column: ``adaptive``, where it was measured); (None, None) otherwise."""
    from gaitml.steps import confident_steps, gait_confidence

    if "confidence" not in steps.columns:
        return None, None
    return gait_confidence(steps), confident_steps(steps)[0]


def _confidence_line(sure: dict, n: int) -> str:
    """The summary line of the confident / unsure verdict."""
    return (
        f"  {n} steps, {sure['n_confident']} confident, {sure['n_unsure']} unsure (confident: within "
        f"{sure['window_s']:g} s of a bout of >= {sure['min_bout_steps']} regular steps; longest bout here "
        f"{sure['longest_bout_steps']})"
    )


def _unsure_note(sure: dict, duration_s: float | None = None, period_s: float | None = None) -> str:
    """The stderr note when most steps are unsure: a recording too short to confirm a walk, or short bursts of steps."""
    n = sure["n_confident"] + sure["n_unsure"]
    # fewer steps than a confirming bout, in a recording shorter than 1.5 x the time one takes at its step period
    if n < sure["min_bout_steps"] and duration_s is not None and period_s and duration_s < 1.5 * sure["min_bout_steps"] * period_s:
        return (
            f"the recording ({duration_s:.1f} s) is too short to confirm gait: a walk is confirmed by a bout of "
            f"{sure['min_bout_steps']} regular steps; its {n} steps are kept in the count and marked unsure"
        )
    head = "no confident gait found" if not sure["n_confident"] else "most steps are unsure"
    return (
        f"{head}: {sure['n_unsure']} of {n} steps have no bout of >= "
        f"{sure['min_bout_steps']} regular steps within {sure['window_s']:g} s (longest bout {sure['longest_bout_steps']}); "
        "they are kept in the count and marked unsure. A phone handled or gestured with, not carried by a walker, gives such steps"
    )


def _with_confident(steps, confident):
    """The step table to write: with a ``confident`` column where the detector's steps got a verdict, and a
    ``rate_reason`` column when a step was recorded below the detector's rate floor (:func:`gaitml.steps.rate_flags`)."""
    from gaitml.steps import add_rate_reasons

    out = steps.copy(deep=False) if confident is None else steps.assign(confident=np.asarray(confident, dtype=bool))
    add_rate_reasons(out, steps)
    return out


def _rate_notes(steps) -> tuple[dict | None, str | None]:
    """The rate check of the step table (:func:`gaitml.steps.rate_record`), its one stderr line, and the summary line
    (None when no step was recorded below the detector's rate floor)."""
    from gaitml.steps import rate_record

    rate = rate_record(steps)
    rate_check_note(rate)
    line = rate_check_summary(rate)
    return rate, None if line is None else f"  {line}"


def _json_rate(obj: dict, steps, rate: dict | None) -> None:
    """Add ``rate_check`` and, when a step is flagged, each step's ``rate_reason`` to the JSON object."""
    from gaitml.steps import rate_flags

    obj["rate_check"] = rate
    flagged, why = rate_flags(steps)
    if flagged.any():
        for step, r in zip(obj["steps"], why, strict=True):
            step["rate_reason"] = str(r) or None


def _notes(steps, checked: dict | None, duration_s: float | None = None) -> tuple[str | None, dict | None, np.ndarray | None]:
    """The stderr notes on the gait check and the confident / unsure verdict; returns (the gait line, verdict, flags).

    ``duration_s`` (the whole recording's) lets a recording too short to confirm a walk be told so.
    """
    gait_line = _gait_line(checked)
    if checked and not checked.get("tested", True):
        log(f"gaitml: note: gait check {gait_line}")
    elif checked and checked["n_steps_rejected"]:
        log(f"gaitml: note: {gait_line}")
    sure, confident = _confidence(steps)
    if sure is not None and sure["n_unsure"] > len(steps) / 2:
        period = float(np.median(steps["period_s"])) if duration_s is not None else None
        log(f"gaitml: note: {_unsure_note(sure, duration_s, period)}")
    return gait_line, sure, confident


def _json_verdicts(obj: dict, checked: dict | None, sure: dict | None, confident: np.ndarray | None) -> None:
    """Add the per-step ``confident`` flags, the verdict keys and the gait-check account to the JSON object."""
    if confident is not None:
        for step, ok in zip(obj["steps"], confident, strict=True):
            step["confident"] = bool(ok)
    if sure is not None:
        obj["n_confident"], obj["n_unsure"] = sure["n_confident"], sure["n_unsure"]
        obj["gait_confidence"] = sure
    if checked is not None:
        obj["gait_check"] = {k: v for k, v in checked.items() if k != "rejected_t_s"}
        obj["gait_check"]["rejected_t_s"] = [float(v) for v in checked["rejected_t_s"]]


def run(args) -> int:
    """Detect steps, print a summary or the JSON contract, optionally write the table."""
    from gaitml.evaluation.steps import step_times
    from gaitml.io import write_csv
    from gaitml.steps import get_detector
    from gaitml.steps._gait_evidence import gait_check_recording
    from gaitml.steps.crosscheck import count_warning

    if is_large_input(args):
        return _run_long(args)
    rec = load_input(args)
    gait = getattr(args, "gait_check", None)
    gait = args.detector in GAIT_CHECK_BY_DEFAULT if gait is None else gait
    if args.detector == "adaptive":  # adaptive runs the test itself
        det = get_detector(args.detector, gait_check=gait).detect(rec)
        steps = det.steps_
    else:
        det = get_detector(args.detector).detect(rec)
        steps = det.steps_
        if gait:  # tested at adaptive's step frequency: a detector counting one step per stride would test its strides
            steps = gait_check_recording(steps, rec)
    checked = steps.attrs.get("gait_check") if gait else None
    gait_line, sure, confident = _notes(steps, checked, rec.duration_s)
    rate, rate_line = _rate_notes(steps)
    if args.out:
        write_csv(args.out, _with_confident(steps, confident))
    ev = _evaluation(rec, steps)
    t = step_times(steps)
    warning = count_warning(rec, len(steps), args.detector)
    if warning:
        log(f"gaitml: warning: {warning}")
    if args.json:
        obj = {
            "detector": args.detector,
            "sampling_rate_hz": float(rec.sampling_rate_hz),
            "n_steps": int(len(steps)),
            "steps": _json_steps(steps, t),
        }
        if warning:
            obj["warnings"] = [warning]
        _json_verdicts(obj, checked, sure, confident)
        _json_rate(obj, steps, rate)
        cadence = _json_cadence(getattr(det, "cadence_", None))
        if cadence is not None:
            obj["cadence"] = cadence
        if ev is not None:
            obj["n_steps_true"] = ev["n_true"]
            obj["evaluation"] = ev
        emit_json(obj)
        return 0
    period = steps["period_s"].to_numpy()
    lines = [
        f"{rec.name}: {len(steps)} steps ({args.detector}, event {steps.attrs.get('event')}) in {rec.duration_s:.1f} s at {rec.sampling_rate_hz:g} Hz",
    ]
    if sure is not None and len(steps):
        lines.append(_confidence_line(sure, len(steps)))
    if len(steps):
        # period_s is the span the detector gives each step; cadence comes from the
        # intervals between step times, and the overall rate includes pauses
        lines.append(f"  step period (period_s, the detector's step span): median {np.median(period):.3f} s, mean {np.mean(period):.3f} s")
        if "confidence" in steps.columns:
            conf = steps["confidence"].to_numpy(dtype=float)
            lines.append(
                f"  step confidence: median {np.median(conf):.2f}, 10th percentile {np.quantile(conf, 0.1):.2f} "
                "(periodicity x timing regularity: ranks steps, no verdict)"
            )
        rate = f"{len(steps) / rec.duration_s * 60:.1f} steps/min averaged over the whole {rec.duration_s:.1f} s (pauses included)"
        if len(steps) >= 2:
            interval = float(np.median(np.diff(t)))
            lines.append(f"  step interval: median {interval:.3f} s = cadence {60.0 / interval:.1f} steps/min while stepping; {rate}")
        else:
            lines.append(f"  rate: {rate}")
    if gait_line:
        lines.append(f"  gait check: {gait_line}")
    if rate_line:
        lines.append(rate_line)
    if ev is not None:
        s = f"  reference: {ev['n_true']} steps, count accuracy {100 * ev['count_accuracy']:.2f} %"
        if "f1" in ev:
            s += f", F1 {ev['f1']:.3f} at {ev['tolerance_s']:g} s (precision {ev['precision']:.3f}, recall {ev['recall']:.3f})"
            if ev.get("timing_offset_s") is not None:
                s += f", timing offset {ev['timing_offset_s']:+.3f} s"
        lines.append(s)
    if args.out:
        lines.append(f"  step table written to {args.out}")
    print("\n".join(lines))
    if not len(steps):
        log(NO_STEPS_NOTE)
    return 0


def _run_long(args) -> int:
    """A long input: chunks of 10 min with 30 s margins (bounded memory, see gaitml.chunked_run)."""
    import pandas as pd

    from gaitml.chunked_run import long_steps
    from gaitml.evaluation.steps import step_times
    from gaitml.io import write_csv
    from gaitml.steps.crosscheck import CROSSCHECK_DETECTOR, FIXED_THRESHOLD_DETECTORS, compare_counts

    # the count cross-check (gaitml.steps.crosscheck) on the whole input: adaptive counted on the same chunks
    also = CROSSCHECK_DETECTOR if args.detector in FIXED_THRESHOLD_DETECTORS else None
    gait = getattr(args, "gait_check", None)
    gait = args.detector in GAIT_CHECK_BY_DEFAULT if gait is None else gait
    # the gait-evidence test per chunk, its account summed over the chunks' core steps (gaitml.chunked_run)
    # with --json, the per-window cadence of the windows centred in each chunk's core, at whole-file times
    steps = long_steps(
        args.input, args.detector, progress=True, count_also=also, gait_check=gait, keep_cadence=bool(args.json), **long_read_kwargs(args)
    )
    checked = steps.attrs.get("gait_check") if gait else None
    # the verdict reads only the global step table (times and periods), so it is the whole file's
    gait_line, sure, confident = _notes(steps, checked)
    rate, rate_line = _rate_notes(steps)
    fs = float(steps.attrs.get("sampling_rate_hz", 0.0))
    if args.out:
        write_csv(args.out, _with_confident(steps, confident))
    t = step_times(steps) if len(steps) else np.zeros(0)
    warning = compare_counts(len(steps), steps.attrs["count_also"]["n_steps"], args.detector) if also else None
    if warning:
        log(f"gaitml: warning: {warning}")
    if args.json:
        obj = {
            "detector": args.detector,
            "sampling_rate_hz": fs,
            "n_steps": int(len(steps)),
            "steps": _json_steps(steps, t) if len(steps) else [],
            "chunked": steps.attrs.get("chunked"),
        }
        if warning:
            obj["warnings"] = [warning]
        _json_verdicts(obj, checked, sure, confident)
        _json_rate(obj, steps, rate)
        cad = steps.attrs.get("cadence")
        cadence = _json_cadence(None if cad is None else pd.DataFrame(cad))
        if cadence is not None:
            obj["cadence"] = cadence
        emit_json(obj)
        return 0
    chunked = steps.attrs.get("chunked") or {}
    print(
        f"{args.input}: {len(steps)} steps ({args.detector}), processed in chunks of {chunked.get('chunk_s', 0) / 60:g} min "
        f"({chunked.get('margin_s', 0):g} s margins) at {fs:g} Hz"
    )
    if sure is not None and len(steps):
        print(_confidence_line(sure, len(steps)))
    if gait_line:
        print(f"  gait check: {gait_line}")
    if rate_line:
        print(rate_line)
    if args.out:
        print(f"  step table written to {args.out}")
    if not len(steps):
        log(NO_STEPS_NOTE)
    return 0
