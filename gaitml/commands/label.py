"""`gaitml label INPUT --intervals FILE [--snap steps|strides|none] [--detector NAME] --out OUT.csv [--report PNG]`.

Writes ``OUT.csv`` (gaitml-csv with the ``label`` column) and beside it
``OUT.step-labels.csv`` (one row per detected step or stride with its label),
both atomically: after a failure neither file is left half-written.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gaitml.commands._args import add_input_options
from gaitml.commands._util import emit_json, gait_check_note, load_input, log, rate_check_note, rate_check_summary
from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError

#: The command's one-line description in ``gaitml --help``.
HELP = "label a recording from time intervals, snapped to detected steps or strides"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml label`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--intervals", metavar="FILE", required=True, help="CSV start_s,end_s,label or an Audacity label track (start<TAB>end<TAB>label)"
    )
    p.add_argument(
        "--snap", choices=("steps", "strides", "none"), default="steps", help="move boundaries to step or stride boundaries (default steps)"
    )
    p.add_argument(
        "--detector",
        help=f"step detector (steps/none; default {DEFAULT_STEP_DETECTOR}) or zero-velocity detector (strides; default pseudo-std)",
    )
    p.add_argument(
        "--boundary",
        choices=("peak", "edges"),
        default="peak",
        help="step boundaries at the step events (default) or the detector's step start/end",
    )
    p.add_argument("--max-snap-s", type=float, default=0.5, help="largest move of a boundary in s (default 0.5)")
    p.add_argument(
        "--boundary-noise-s",
        type=float,
        help="the most a written boundary is off (s): the search band for the mode change (rule change; default: "
        "--max-snap-s); with --snap-rule nearest, snap only to a single step within it",
    )
    p.add_argument(
        "--snap-rule",
        choices=("change", "nearest"),
        default="change",
        help="move a boundary only to evidence of the mode change (default; otherwise it stays, 'ambiguous') or to the nearest step",
    )
    p.add_argument("--unlabelled", default="unlabelled", help="label of samples outside every interval (default unlabelled)")
    p.add_argument("--out", metavar="OUT.csv", required=True, help="labelled gaitml-csv; OUT.step-labels.csv is written beside it")
    p.add_argument("--report", metavar="PNG", help="plot the signal, intervals, steps and snapped boundaries")
    p.add_argument("--json", action="store_true")
    add_input_options(p)


#: Suffix of the per-step label table written beside OUT.csv.
STEP_LABELS_SUFFIX = ".step-labels.csv"


def step_labels_path(out: str | Path) -> Path:
    """``OUT.csv`` -> ``OUT.step-labels.csv``."""
    p = Path(out)
    name = p.name[: -len(".csv")] if p.name.endswith(".csv") else p.name
    return p.with_name(name + STEP_LABELS_SUFFIX)


def run(args) -> int:
    from gaitml.io._atomic import atomic_path
    from gaitml.io.gaitml_csv import write_gaitml_csv
    from gaitml.labels import label_recording, plot_label_report, read_intervals

    out = Path(args.out)
    if not out.name.endswith(".csv"):
        raise InputError(f"--out {out} must be a .csv file (the labelled gaitml-csv); e.g. --out walk.labelled.csv.")
    if out.name.endswith(STEP_LABELS_SUFFIX):
        raise InputError(f"--out {out.name} ends like the per-step table it writes beside it; choose another name, e.g. walk.labelled.csv.")
    rec = load_input(args)
    intervals = read_intervals(args.intervals)
    lab = label_recording(
        rec,
        intervals,
        snap=args.snap,
        detector=args.detector,
        max_snap_s=args.max_snap_s,
        unlabelled=args.unlabelled,
        boundary=args.boundary,
        noise_s=args.boundary_noise_s,
        rule=args.snap_rule,
    )
    side = step_labels_path(out)
    # the per-step table is moved into place only after the recording was written (atomically)
    with atomic_path(side) as tmp_side:
        lab.steps_.to_csv(tmp_side, index=False)
        write_gaitml_csv(lab.recording_, out)
    if args.report:
        plot_label_report(lab, args.report)
    r = lab.report_
    gait_check_note(r.get("gait_check"), r["detector"])
    rate_check_note(r.get("rate_check"))  # steps recorded below the detector's rate floor (gaitml.steps._rate)
    if args.json:
        emit_json(
            {"out": str(out), "step_labels": str(side), "report_png": args.report, "intervals": lab.intervals_.to_dict("records"), **r}
        )
        return 0
    unit = "strides" if args.snap == "strides" else "steps"
    lines = [
        f"{rec.name}: {r['n_intervals']} intervals, {r['n_boundaries']} boundaries; "
        + (
            f"{r['n_snapped']} snapped to {unit} of {r['detector']} within {r['max_snap_s']:g} s "
            f"(mean shift {r['mean_abs_shift_s']:.3f} s, max {r['max_abs_shift_s']:.3f} s)"
            if args.snap != "none"
            else "not snapped (--snap none)"
        ),
    ]
    for t, status in r["not_snapped"] if args.snap != "none" else []:
        lines.append(f"  boundary at {t:.3f} s kept as written: {status}")
    lines.append("  samples per label: " + ", ".join(f"{k} {v}" for k, v in r["labels"].items()))
    lines.append(f"  {r['n_steps']} {unit} labelled ({r['n_mixed_steps']} span a boundary: label_fraction < 1)")
    rate = rate_check_summary(r.get("rate_check"))  # the stderr warning's summary (gaitml.steps._rate)
    if rate:
        lines.append(f"  {rate.replace('(rate_reason)', f'(rate_reason in {side.name})')}")
    if rec.labels is not None:
        lines.append("  note: the input's own labels were replaced by the intervals'")
    lines.append(f"  written: {out}, {side}" + (f", {args.report}" if args.report else ""))
    print("\n".join(lines))
    if r["not_snapped"] and args.snap != "none":
        log(
            f"note: {len(r['not_snapped'])} boundaries had no {unit[:-1]} boundary within {r['max_snap_s']:g} s"
            + (" or no clean evidence of the mode change there" if r["rule"] == "change" else "")
            + (" or more than one within the stated noise" if r["noise_s"] is not None and r["rule"] == "nearest" else "")
            + " and stay where they were written."
        )
    return 0
