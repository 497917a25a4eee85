"""`gaitml zupt INPUT [--detector NAME] [--threshold-rads X] [--out FILE] [--json]` (DESIGN sec. 5).

Inputs longer than ``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` are processed in
overlapping chunks (:func:`gaitml.chunked_run.long_zupts`, bounded memory, the same
per-sample decisions as a whole-file run); the others are read whole.
"""

from __future__ import annotations

import numpy as np

from gaitml.commands._util import emit_json, is_large_input, load_input, log, long_read_kwargs
from gaitml.errors import InputError
from gaitml.io import write_csv
from gaitml.zupt import get_detector

#: detectors whose threshold ``--threshold-rads`` sets, and the parameter it maps to
THRESHOLD_PARAM = {"pseudo-std": "threshold_rads"}


def detector_params(detector: str, threshold_rads: float | None) -> dict:
    """Constructor parameters from the CLI options (``--threshold-rads``)."""
    if threshold_rads is None:
        return {}
    if detector not in THRESHOLD_PARAM:
        raise InputError(
            f"--threshold-rads applies to {', '.join(THRESHOLD_PARAM)} only, not {detector!r}; drop it or use --detector pseudo-std."
        )
    if not np.isfinite(threshold_rads) or threshold_rads <= 0:
        raise InputError(f"--threshold-rads must be a positive number of rad/s, got {threshold_rads!r}.")
    return {THRESHOLD_PARAM[detector]: float(threshold_rads)}


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


def zupt_summary(rec, detector: str = "pseudo-std", threshold_rads: float | None = None) -> tuple[object, dict]:
    """Run a detector on a recording and build the JSON object (library entry point)."""
    det = get_detector(detector, **detector_params(detector, threshold_rads)).detect(rec)
    obj = summary(
        detector,
        det.per_sample_zupts_,
        det.zupts_,
        rec.sampling_rate_hz,
        threshold_rads=getattr(det, "threshold_rads_", None),
        stride_events=rec.reference.get("stride_events"),
    )
    return det, obj


def run(args) -> int:
    """Detect zero-velocity intervals; print a summary or the JSON contract; optionally write the table."""
    params = detector_params(args.detector, args.threshold_rads)
    if is_large_input(args):
        from gaitml.chunked_run import long_zupts

        kw = long_read_kwargs(args)
        mask, table, fs = long_zupts(
            args.input,
            args.detector,
            detector_params=params,
            progress=True,
            **kw,
        )
        thr = getattr(get_detector(args.detector, **params), "_threshold", lambda: None)()
        obj = summary(args.detector, mask, table, fs, threshold_rads=thr)
        name, n = args.input, len(mask)
    else:
        rec = load_input(args)
        det, obj = zupt_summary(rec, args.detector, args.threshold_rads)
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
