"""`gaitml zupt INPUT [--detector NAME] [--threshold-rads X] [--interval-rules R] [--out FILE] [--json]` (DESIGN sec. 5).

Inputs longer than ``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` are processed in
overlapping chunks (:func:`gaitml.chunked_run.long_zupts`, bounded memory, the same
per-sample decisions as a whole-file run); the others are read whole.
"""

from __future__ import annotations

import argparse

import numpy as np

from gaitml.commands._args import add_input_options, choices, zupt_detectors
from gaitml.commands._util import emit_json, is_large_input, load_input, log, long_read_kwargs
from gaitml.errors import InputError

#: The command's one-line description in ``gaitml --help``.
HELP = "detect zero-velocity intervals"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml zupt`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--detector", **choices("zupt", "--detector", zupt_detectors), default="pseudo-std", help="%(choices)s (default %(default)s)"
    )
    p.add_argument("--threshold-rads", type=float, help="detector threshold in rad/s (pseudo-std)")
    p.add_argument(
        "--interval-rules",
        choices=("stride", "fixed", "none"),
        help="pseudo-std, magnitude: stride (default: follow the local stride period), fixed (seconds), none (per-sample rule)",
    )
    p.add_argument("--out", metavar="FILE", help="write the interval table as CSV")
    p.add_argument("--json", action="store_true")
    add_input_options(p)


#: detectors whose threshold ``--threshold-rads`` sets, and the parameter it maps to
THRESHOLD_PARAM = {"pseudo-std": "threshold_rads"}
#: detectors with interval rules (``--interval-rules``)
INTERVAL_RULE_DETECTORS = ("pseudo-std", "magnitude")


def interval_rule_params(detector: str, interval_rules: str | None) -> dict:
    """``{'interval_rules': ...}`` from ``--interval-rules`` (empty when not given); InputError for a detector without rules."""
    if interval_rules is None:
        return {}
    if detector not in INTERVAL_RULE_DETECTORS:
        raise InputError(
            f"--interval-rules applies to {', '.join(INTERVAL_RULE_DETECTORS)} only, not {detector!r}; drop it or choose one of those."
        )
    return {"interval_rules": interval_rules}


def detector_params(detector: str, threshold_rads: float | None, interval_rules: str | None = None) -> dict:
    """Constructor parameters from the CLI options (``--threshold-rads``, ``--interval-rules``)."""
    rules = interval_rule_params(detector, interval_rules)
    if threshold_rads is None:
        return rules
    if detector not in THRESHOLD_PARAM:
        raise InputError(
            f"--threshold-rads applies to {', '.join(THRESHOLD_PARAM)} only, not {detector!r}; drop it or use --detector pseudo-std."
        )
    if not np.isfinite(threshold_rads) or threshold_rads <= 0:
        raise InputError(f"--threshold-rads must be a positive number of rad/s, got {threshold_rads!r}.")
    return {THRESHOLD_PARAM[detector]: float(threshold_rads), **rules}


def summary(
    detector: str, mask: np.ndarray, table, sampling_rate_hz: float, *, threshold_rads: float | None = None, stride_events=None
) -> dict:
    """The JSON object of the CLI contract from a mask and its interval table."""
    obj = {
        "detector": detector,
        "sampling_rate_hz": float(sampling_rate_hz),
        "n_intervals": int(len(table)),
        "intervals": [{"t_start_s": float(a), "t_end_s": float(b)} for a, b in zip(table["t_start_s"], table["t_end_s"], strict=True)],
        "zero_velocity_fraction": float(np.mean(mask)) if len(mask) else 0.0,
    }
    if threshold_rads is not None:
        obj["threshold_rads"] = float(threshold_rads)
    if stride_events is not None and len(stride_events):
        from gaitml.evaluation.zupt import evaluate_stride_events

        obj["evaluation"] = evaluate_stride_events(table, stride_events)
    return obj


def zupt_summary(
    rec, detector: str = "pseudo-std", threshold_rads: float | None = None, interval_rules: str | None = None
) -> tuple[object, dict]:
    """Run a detector on a recording and build the JSON object (library entry point)."""
    from gaitml.zupt import get_detector

    det = get_detector(detector, **detector_params(detector, threshold_rads, interval_rules)).detect(rec)
    obj = summary(
        detector,
        det.per_sample_zupts_,
        det.zupts_,
        rec.sampling_rate_hz,
        threshold_rads=getattr(det, "threshold_rads_", None),
        stride_events=rec.reference.get("stride_events"),
    )
    if hasattr(det, "interval_rules"):
        obj["interval_rules"] = det.interval_rules
    return det, obj


def run(args) -> int:
    """Detect zero-velocity intervals; print a summary or the JSON contract; optionally write the table."""
    from gaitml.io import write_csv
    from gaitml.zupt import get_detector

    rules = getattr(args, "interval_rules", None)
    params = detector_params(args.detector, args.threshold_rads, rules)
    if is_large_input(args):
        from gaitml.chunked_run import long_zupts

        mask, table, fs = long_zupts(
            args.input,
            args.detector,
            detector_params=params,
            progress=True,
            **long_read_kwargs(args),
        )
        det = get_detector(args.detector, **params)
        thr = getattr(det, "_threshold", lambda: None)()
        obj = summary(args.detector, mask, table, fs, threshold_rads=thr)
        if hasattr(det, "interval_rules"):  # as zupt_summary reports it for a file read whole
            obj["interval_rules"] = det.interval_rules
        name, n = args.input, len(mask)
    else:
        rec = load_input(args)
        det, obj = zupt_summary(rec, args.detector, args.threshold_rads, rules)
        table, fs, name, n = det.zupts_, rec.sampling_rate_hz, rec.name, rec.n_samples
    if args.out:
        write_csv(args.out, table)
    if args.json:
        emit_json(obj)
        return 0
    lines = [
        f"{name}: {obj['n_intervals']} zero-velocity intervals ({args.detector}), "
        f"{100 * obj['zero_velocity_fraction']:.1f} % of {n} samples at {fs:g} Hz"
    ]
    if "threshold_rads" in obj:
        lines.append(f"  threshold {obj['threshold_rads']:.4f} rad/s ({np.degrees(obj['threshold_rads']):.2f} deg/s)")
    ev = obj.get("evaluation")
    if ev:
        lines.append(
            f"  reference: {ev['n_strides']} strides; min_vel inside a detection {100 * ev['min_vel_recall']:.1f} %, "
            f"stances split {100 * ev['split_fraction']:.1f} %, count accuracy {100 * ev['count_accuracy']:.1f} %"
        )
    print("\n".join(lines))
    if args.out:
        log(f"wrote {len(table)} intervals to {args.out}")
    return 0
