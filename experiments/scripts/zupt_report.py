"""The zero-velocity table on the gaitmap example walk (both feet, every detector).

Run ``python -m experiments.scripts.zupt_report`` (``--json`` for one JSON object, ``--data``
for another copy of ``imu_sample.csv.gz``). For each detector and foot: the share
of strides whose motion-capture ``min_vel`` sample lies inside a detected
zero-velocity interval, the share of strides whose stance ``[pre_ic, tc)`` is split
into more than one interval, intervals per stance, paper 001's count accuracy,
and the zupt-magnitude step count against the number of strides.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from gaitml.evaluation.zupt import evaluate_stride_events, per_sample_scores
from gaitml.io import read_recording
from gaitml.zupt import DETECTORS, get_detector, reference_zupt_mask

__all__ = ["default_data_path", "zupt_table", "step_count_table", "format_markdown", "main"]

#: pass bounds of the table: min_vel recall and the share of split stances
MIN_RECALL = 0.95
MAX_SPLIT = 0.05


def default_data_path() -> Path:
    """``../shared/data/gaitmap-example/imu_sample.csv.gz`` next to the checkout (or $GAITML_SHARED_DATA)."""
    import os

    root = Path(__file__).resolve().parents[2]
    base = Path(os.environ.get("GAITML_SHARED_DATA", root.parent / "shared" / "data"))
    return base / "gaitmap-example" / "imu_sample.csv.gz"


def _row(config: str, foot: str, det, rec, fitted_on: str | None = None) -> dict:
    ev = evaluate_stride_events(det, rec.reference["stride_events"])
    ev.pop("n_split", None)
    row = {"detector": config, "foot": foot, "fitted_on": fitted_on or "", **ev}
    # per-sample recall on the labelled samples (+-50 ms around each min_vel); there is no
    # full per-sample truth in this data set, so precision/F1 are not meaningful here
    row["labelled_sample_recall"] = per_sample_scores(det.per_sample_zupts_, reference_zupt_mask(rec))["recall"]
    thr = getattr(det, "threshold_rads_", None)
    if thr is not None:
        row["threshold_degs"] = float(np.degrees(thr))
    if getattr(det, "gamma_", None) is not None:
        row["gamma"] = float(det.gamma_)
    if getattr(det, "t_min_ms2_", None) is not None:
        row["band_ms2"] = [round(det.t_min_ms2_, 3), round(det.t_max_ms2_, 3)]
    row["passes"] = bool(row["min_vel_recall"] >= MIN_RECALL and row["split_fraction"] <= MAX_SPLIT)
    return row


def zupt_table(path: str | Path | None = None) -> list[dict]:
    """Rows of the table: every detector with its defaults on both feet, then fitted variants.

    Fitted rows: threshold fitted on one foot's labelled samples (50 ms around each
    ``min_vel``) and tested on the other foot (both directions), for every detector
    with a ``fit``.
    """
    p = Path(path) if path is not None else default_data_path()
    recs = {foot: read_recording(p, sensor=foot) for foot in ("left", "right")}
    rows = []
    for name in DETECTORS:
        for foot, rec in recs.items():
            rows.append(_row(name, foot, get_detector(name).detect(rec), rec))
    for name in DETECTORS:
        if not hasattr(DETECTORS[name], "fit"):
            continue
        for train, test in (("left", "right"), ("right", "left")):
            det = get_detector(name).fit([recs[train]])
            rows.append(_row(f"{name} (fitted)", test, det.detect(recs[test]), recs[test], fitted_on=train))
    return rows


def half_window_sensitivity(path: str | Path | None = None, half_windows_s=(0.02, 0.035, 0.05, 0.075, 0.1)) -> list[dict]:
    """pseudo-std with the paper threshold for several half-windows (s is not printed in paper 001)."""
    p = Path(path) if path is not None else default_data_path()
    rows = []
    for foot in ("left", "right"):
        rec = read_recording(p, sensor=foot)
        for h in half_windows_s:
            rows.append(_row(f"pseudo-std half_window_s={h}", foot, get_detector("pseudo-std", half_window_s=h).detect(rec), rec))
    return rows


def step_count_table(path: str | Path | None = None) -> list[dict]:
    """zupt-magnitude step counts per foot against the number of strides.

    ``n_steps`` counts every step the detector reports over the whole recording
    (which also holds gait initiation/termination steps and turning shuffles that
    gaitmap does not annotate); ``n_steps_in_span`` counts the steps whose landing
    (interval start) falls inside the annotated walk, after the first stride's
    start and up to the last stride's end: exactly one per annotated stride when
    the counter is right.
    """
    from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector

    p = Path(path) if path is not None else default_data_path()
    out = []
    for foot in ("left", "right"):
        rec = read_recording(p, sensor=foot)
        ev = rec.reference["stride_events"]
        steps = ZuptMagnitudeStepDetector().detect(rec).steps_
        lo, hi = float(ev["start"].min()), float(ev["end"].max())
        inside = int(((steps["start"] > lo) & (steps["start"] <= hi)).sum())
        n_strides = int(len(ev))
        out.append(
            {
                "foot": foot,
                "n_strides": n_strides,
                "n_steps": int(len(steps)),
                "n_steps_in_span": inside,
                "error_in_span": inside - n_strides,
                "within_1": abs(inside - n_strides) <= 1,
            }
        )
    return out


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.3f}"
    return str(v)


def format_markdown(rows: list[dict], columns: list[str]) -> str:
    """A markdown table of ``rows`` restricted to ``columns``."""
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        lines.append("| " + " | ".join(_fmt(r.get(c, "")) for c in columns) + " |")
    return "\n".join(lines)


ZUPT_COLUMNS = [
    "detector",
    "foot",
    "fitted_on",
    "threshold_degs",
    "gamma",
    "band_ms2",
    "n_strides",
    "min_vel_recall",
    "labelled_sample_recall",
    "split_fraction",
    "intervals_per_stance",
    "stride_extra_fraction",
    "n_intervals",
    "n_intervals_in_span",
    "n_stances_in_span",
    "count_accuracy",
    "passes",
]
STEP_COLUMNS = ["foot", "n_strides", "n_steps", "n_steps_in_span", "error_in_span", "within_1"]


def main(argv: list[str] | None = None) -> int:
    """Print the tables (markdown, or one JSON object with ``--json``)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.zupt_report", description=__doc__.splitlines()[0])
    ap.add_argument("--data", help="path of gaitmap's imu_sample.csv.gz (default: ../shared/data/gaitmap-example/)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--sensitivity", action="store_true", help="also the pseudo-std half-window sensitivity")
    args = ap.parse_args(argv)
    rows = zupt_table(args.data)
    steps = step_count_table(args.data)
    sens = half_window_sensitivity(args.data) if args.sensitivity else []
    if args.json:
        json.dump(
            {"zupt": rows, "steps": steps, "sensitivity": sens},
            sys.stdout,
            default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o),
        )
        sys.stdout.write("\n")
        return 0
    print(f"Zero-velocity detection on {args.data or default_data_path()} (pass: min_vel recall >= {MIN_RECALL}, split <= {MAX_SPLIT})\n")
    print(format_markdown(rows, ZUPT_COLUMNS))
    print("\nzupt-magnitude step counting (paper 004)\n")
    print(format_markdown(steps, STEP_COLUMNS))
    if sens:
        print("\npseudo-std (paper threshold) vs half-window\n")
        print(format_markdown(sens, ZUPT_COLUMNS))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
