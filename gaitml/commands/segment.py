"""`gaitml segment INPUT --by steps|strides|zupt [--detector NAME] [--interval-rules R] --out FILE [--json]`.

Writes the segment table of :func:`gaitml.segment.segment` as CSV, atomically (a
failed run leaves no file). The detector is checked against the registry of the
chosen ``--by`` (step detectors for ``steps``; zero-velocity detectors for
``strides`` and ``zupt``) before the input is read.
"""

from __future__ import annotations

import argparse
import math

from gaitml.commands._args import add_input_options
from gaitml.commands._util import emit_json, gait_check_note, load_input, log, rate_check_note, rate_check_summary
from gaitml.consts import DEFAULT_STEP_DETECTOR

#: The command's one-line description in ``gaitml --help``.
HELP = "cut a recording into steps, strides or zero-velocity intervals (a table of segments)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml segment`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--by", choices=("steps", "strides", "zupt"), default="steps", help="%(choices)s (default %(default)s)")
    p.add_argument(
        "--detector",
        help=f"step detector for --by steps (default {DEFAULT_STEP_DETECTOR}), zero-velocity detector for strides/zupt (default pseudo-std)",
    )
    p.add_argument(
        "--interval-rules",
        choices=("stride", "fixed", "none"),
        help="strides/zupt with pseudo-std or magnitude: stride (default), fixed, none (the per-sample rule)",
    )
    p.add_argument("--out", metavar="FILE", required=True, help="write the segment table as CSV")
    p.add_argument("--json", action="store_true")
    add_input_options(p)


def _num(x) -> float | None:
    x = float(x)
    return None if math.isnan(x) else x


def run(args) -> int:
    """Segment a recording; write the table; print a summary or the JSON object."""
    from gaitml.io import write_csv
    from gaitml.segment import resolve_detector, segment

    det = resolve_detector(args.by, args.detector)  # a bad name fails before any reading
    rules = getattr(args, "interval_rules", None)
    if rules is not None:
        from gaitml.commands.zupt import interval_rule_params
        from gaitml.errors import InputError

        if args.by == "steps":
            raise InputError("--interval-rules applies to --by strides and --by zupt (zero-velocity detectors); drop it for --by steps.")
        det = type(det)(**{**det.get_params(), **interval_rule_params(det.name, rules)})
    rec = load_input(args)
    table = segment(rec, by=args.by, detector=det)
    write_csv(args.out, table)
    name = table.attrs["detector"]
    gait = table.attrs.get("gait_check")
    gait_check_note(gait, name)
    rate = table.attrs.get("rate_check")  # steps recorded below the detector's rate floor (gaitml.steps._rate)
    rate_check_note(rate)
    flagged = "rate_reason" in table.columns
    if args.json:
        emit_json(
            {
                "by": args.by,
                "detector": name,
                "sampling_rate_hz": float(rec.sampling_rate_hz),
                "n_segments": int(len(table)),
                "out": str(args.out),
                "segments": [
                    {
                        "start_s": float(a),
                        "end_s": float(b),
                        "duration_s": float(d),
                        "confidence": _num(c),
                        **({"rate_reason": str(table["rate_reason"].iloc[i]) or None} if flagged else {}),
                    }
                    for i, (a, b, d, c) in enumerate(
                        zip(table["start_s"], table["end_s"], table["duration_s"], table["confidence"], strict=True)
                    )
                ],
                **({"gait_check": gait} if gait is not None else {}),
                **({"rate_check": rate} if args.by == "steps" else {}),
            }
        )
        return 0
    dur = table["duration_s"]
    what = {"steps": "steps", "strides": "strides", "zupt": "zero-velocity intervals"}[args.by]
    line = f"{rec.name}: {len(table)} {what} ({name})"
    if len(table):
        line += f", duration median {dur.median():.3f} s (min {dur.min():.3f}, max {dur.max():.3f})"
    summary = rate_check_summary(rate)  # the stderr warning's summary (gaitml.steps._rate)
    if summary:
        line += f"; {summary}"
    print(line)
    log(f"wrote {len(table)} segments to {args.out}")
    return 0
