"""`gaitml zupt INPUT [--detector NAME] [--threshold-rads X] [--out FILE] [--json]` (DESIGN sec. 5)."""

from __future__ import annotations

import numpy as np

from gaitml.commands._util import emit_json, load_input, log
from gaitml.errors import InputError
from gaitml.io import write_csv
from gaitml.zupt import get_detector

#: detectors whose threshold ``--threshold-rads`` sets, and the parameter it maps to
THRESHOLD_PARAM = {"pseudo-std": "threshold_rads"}


def zupt_summary(rec, detector: str = "pseudo-std", threshold_rads: float | None = None) -> tuple[object, dict]:
    """Run a detector and build the JSON object of the CLI contract (library entry point)."""
    params = {}
    if threshold_rads is not None:
        if detector not in THRESHOLD_PARAM:
            raise InputError(
                f"--threshold-rads applies to {', '.join(THRESHOLD_PARAM)} only, not {detector!r}; drop it or use --detector pseudo-std."
            )
        if not np.isfinite(threshold_rads) or threshold_rads <= 0:
            raise InputError(f"--threshold-rads must be a positive number of rad/s, got {threshold_rads!r}.")
        params[THRESHOLD_PARAM[detector]] = float(threshold_rads)
    det = get_detector(detector, **params).detect(rec)
    z = det.zupts_
    obj = {
        "detector": detector,
        "sampling_rate_hz": float(rec.sampling_rate_hz),
        "n_intervals": int(len(z)),
        "intervals": [{"t_start_s": float(a), "t_end_s": float(b)} for a, b in zip(z["t_start_s"], z["t_end_s"], strict=True)],
        "zero_velocity_fraction": float(np.mean(det.per_sample_zupts_)),
    }
    thr = getattr(det, "threshold_rads_", None)
    if thr is not None:
        obj["threshold_rads"] = float(thr)
    ev = rec.reference.get("stride_events")
    if ev is not None and len(ev):
        from gaitml.evaluation.zupt import evaluate_stride_events

        obj["evaluation"] = evaluate_stride_events(det, ev)
    return det, obj


def run(args) -> int:
    """Detect zero-velocity intervals; print a summary or the JSON contract; optionally write the table."""
    rec = load_input(args)
    det, obj = zupt_summary(rec, args.detector, args.threshold_rads)
    if args.out:
        write_csv(args.out, det.zupts_)
    if args.json:
        emit_json(obj)
        return 0
    lines = [
        f"{rec.name}: {obj['n_intervals']} zero-velocity intervals ({args.detector}), "
        f"{100 * obj['zero_velocity_fraction']:.1f} % of {rec.n_samples} samples at {rec.sampling_rate_hz:g} Hz"
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
        log(f"wrote {len(det.zupts_)} intervals to {args.out}")
    return 0
