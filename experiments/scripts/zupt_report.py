"""The zero-velocity table on the gaitmap example walk (both feet, every detector).

Run ``python -m experiments.scripts.zupt_report`` (``--json`` for one JSON object, ``--data``
for another copy of ``imu_sample.csv.gz``). For each detector and foot: the share
of strides whose motion-capture ``min_vel`` sample lies inside a detected
zero-velocity interval, the share of strides whose stance ``[pre_ic, tc)`` is split
into more than one interval, intervals per stance, spurious intervals per stance,
paper 001's count accuracy, and the zupt-magnitude step count against the number
of strides.

``--heldout`` adds the issue-13 tables (experiments/reports/zupt-heldout.md):

- fitted thresholds, in-sample beside held-out: leave-one-foot-out on the labelled
  walk (fit on one foot's ``min_vel`` samples, score on the same foot and on the
  other), and leave-one-trial-out (fit on the walk, score on the other trials);
- pseudo-std before (paper 001's per-sample rule alone) and after the interval
  rules on every gaitmap trial: the labelled walk (motion capture), the 4 x 10 m walk
  (initial-contact strides from motion capture), stairs up/down and the patient's
  walk (no labels: swing-bracketed counts, see :func:`swing_bracketed_counts`);
- a synthetic running foot signal (no shared data has running), a sanity check only.
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

__all__ = [
    "default_data_path",
    "zupt_table",
    "step_count_table",
    "format_markdown",
    "heldout_fit_table",
    "trial_table",
    "swing_bracketed_counts",
    "synthetic_running_foot",
    "running_table",
    "main",
]

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
    "spurious_per_stance",
    "passes",
]
STEP_COLUMNS = ["foot", "n_strides", "n_steps", "n_steps_in_span", "error_in_span", "within_1"]


#: the gaitmap trials of the held-out tables: (file stem, sensor, kind)
TRIALS = [
    ("imu_sample", "left", "walk (mocap min_vel)"),
    ("imu_sample", "right", "walk (mocap min_vel)"),
    ("imu_sample_ic_stride", "left", "walk 4x10 m (mocap IC strides)"),
    ("imu_sample_ic_stride", "right", "walk 4x10 m (mocap IC strides)"),
    ("imu_sample_healthy_stair_up", "left", "stairs up (no labels)"),
    ("imu_sample_healthy_stair_up", "right", "stairs up (no labels)"),
    ("imu_sample_healthy_stair_down", "left", "stairs down (no labels)"),
    ("imu_sample_healthy_stair_down", "right", "stairs down (no labels)"),
    ("imu_sample_ms_left", None, "patient walk (no labels)"),
    ("imu_sample_ms_right", None, "patient walk (no labels)"),
]

#: swing-peak detection of :func:`swing_bracketed_counts`: the gyro magnitude of a
#: foot peaks once per swing at several hundred deg/s; 150 deg/s height and 100 deg/s
#: prominence are far above any stance and far below any swing of these trials, and
#: two swings of one foot are at least one stride (> 0.6 s) apart.
SWING_PEAK_DEGS = 150.0
SWING_PROMINENCE_DEGS = 100.0
SWING_MIN_DISTANCE_S = 0.6


def _read_trial(folder: Path, stem: str, sensor: str | None):
    kw = {"sensor": sensor} if sensor else {}
    return read_recording(folder / f"{stem}.csv.gz", **kw)


def swing_bracketed_counts(rec, mask) -> dict:
    """Label-free stance check: detected intervals between consecutive swing peaks.

    Between two swings of one foot there is exactly one stance. The swings are the
    peaks of the gyro magnitude (:data:`SWING_PEAK_DEGS`, ...); for each pair of
    consecutive peaks the detected intervals lying wholly between them are counted:
    ``spurious`` sums the counts above one, ``missed`` the pairs with none. A proxy,
    not a truth: it is shown beside the motion-capture figures on the labelled walk.
    """
    from scipy.signal import find_peaks

    from gaitml.zupt import mask_runs

    fs = rec.sampling_rate_hz
    g = np.degrees(np.linalg.norm(rec.gyr, axis=1))
    pk, _ = find_peaks(g, height=SWING_PEAK_DEGS, prominence=SWING_PROMINENCE_DEGS, distance=max(1, int(SWING_MIN_DISTANCE_S * fs)))
    s, e = mask_runs(np.asarray(mask, dtype=bool))
    c = np.array([np.sum((s >= a) & (e <= b)) for a, b in zip(pk[:-1], pk[1:], strict=True)], dtype=np.int64)
    n = int(len(c))
    spurious = int(np.maximum(c - 1, 0).sum())
    missed = int(np.sum(c == 0))
    return {
        "n_stances": n,
        "n_spurious": spurious,
        "n_missed": missed,
        "spurious_per_stance": spurious / n if n else float("nan"),
        "stance_hit_rate": 1 - missed / n if n else float("nan"),
    }


def ic_stride_counts(rec, mask) -> dict:
    """Detected intervals per initial-contact stride (``reference['strides']`` of the 4 x 10 m walk).

    A stride from one initial contact to the next holds exactly one stance; an interval
    belongs to the stride its midpoint falls in.
    """
    from gaitml.zupt import mask_runs

    st = rec.reference["strides"]
    s, e = mask_runs(np.asarray(mask, dtype=bool))
    mid = (s + e) / 2
    c = np.array([np.sum((mid >= a) & (mid < b)) for a, b in zip(st["start"], st["end"], strict=True)], dtype=np.int64)
    n = int(len(c))
    spurious = int(np.maximum(c - 1, 0).sum())
    missed = int(np.sum(c == 0))
    return {
        "n_stances": n,
        "n_spurious": spurious,
        "n_missed": missed,
        "spurious_per_stance": spurious / n,
        "stance_hit_rate": 1 - missed / n,
    }


def _trial_scores(rec, det, kind: str) -> dict:
    mask = det.per_sample_zupts_
    out: dict = {"n_intervals": int(len(det.zupts_))}
    if "stride_events" in rec.reference:
        ev = evaluate_stride_events(det, rec.reference["stride_events"])
        out.update(
            reference="mocap min_vel",
            n_stances=ev["n_stances_in_span"],
            n_spurious=ev["n_spurious"],
            spurious_per_stance=ev["spurious_per_stance"],
            min_vel_hit_rate=ev["min_vel_recall"],
        )
        proxy = swing_bracketed_counts(rec, mask)
        out["proxy_spurious_per_stance"] = proxy["spurious_per_stance"]
        out["proxy_stance_hit_rate"] = proxy["stance_hit_rate"]
    elif "strides" in rec.reference:
        out.update(reference="mocap IC strides", **ic_stride_counts(rec, mask), min_vel_hit_rate=float("nan"))
    else:
        out.update(reference="swing peaks (proxy)", **swing_bracketed_counts(rec, mask), min_vel_hit_rate=float("nan"))
    return out


#: pseudo-std variants of the before/after table
BEFORE = {"merge_gap_s": 0.0, "min_interval_s": 0.0}


def trial_table(folder: str | Path | None = None, detector: str = "pseudo-std") -> list[dict]:
    """pseudo-std (paper threshold) before (per-sample rule alone) and after the interval rules, every trial."""
    base = Path(folder) if folder is not None else default_data_path().parent
    rows = []
    for stem, sensor, kind in TRIALS:
        f = base / f"{stem}.csv.gz"
        if not f.exists():
            continue
        rec = _read_trial(base, stem, sensor)
        for variant, params in (("before (per-sample rule)", BEFORE), ("after (interval rules)", {})):
            det = get_detector(detector, **params).detect(rec)
            rows.append(
                {
                    "trial": stem.replace("imu_sample", "").strip("_") or "walk",
                    "foot": sensor or stem.rsplit("_", 1)[-1],
                    "kind": kind,
                    "variant": variant,
                    **_trial_scores(rec, det, kind),
                }
            )
    return rows


def heldout_fit_table(folder: str | Path | None = None) -> list[dict]:
    """Fitted thresholds in-sample beside held-out.

    Leave-one-foot-out on the labelled walk: for each detector with ``fit`` and each
    test foot, the threshold fitted on that foot (in-sample) and on the other foot
    (held out), both scored on the test foot. Leave-one-trial-out: fitted on both feet
    of the walk, scored on every other trial (all held out; no labels to fit there).
    """
    base = Path(folder) if folder is not None else default_data_path().parent
    walk = {foot: _read_trial(base, "imu_sample", foot) for foot in ("left", "right")}
    rows = []
    fitted = [n for n in DETECTORS if hasattr(DETECTORS[n], "fit")]
    for name in fitted:
        for test in ("left", "right"):
            other = "right" if test == "left" else "left"
            row = {"detector": name, "test": f"walk {test}", "protocol": "leave-one-foot-out"}
            for tag, train in (("in_sample", test), ("held_out", other)):
                det = get_detector(name).fit([walk[train]])
                d = det.detect(walk[test])
                ev = evaluate_stride_events(d, walk[test].reference["stride_events"])
                row[f"{tag}_fit_on"] = train
                row[f"{tag}_threshold"] = _threshold_repr(d)
                row[f"{tag}_min_vel_hit_rate"] = ev["min_vel_recall"]
                row[f"{tag}_spurious_per_stance"] = ev["spurious_per_stance"]
            rows.append(row)
        det_walk = get_detector(name).fit([walk["left"], walk["right"]])
        for stem, sensor, kind in TRIALS[2:]:
            if not (base / f"{stem}.csv.gz").exists():
                continue
            rec = _read_trial(base, stem, sensor)
            default = _trial_scores(rec, get_detector(name).detect(rec), kind)
            held = _trial_scores(rec, det_walk.detect(rec), kind)
            rows.append(
                {
                    "detector": name,
                    "test": f"{stem.replace('imu_sample_', '')} {sensor or ''}".strip(),
                    "protocol": "leave-one-trial-out (fit: walk, both feet)",
                    "in_sample_fit_on": "(default threshold)",
                    "in_sample_threshold": _threshold_repr(get_detector(name).detect(rec)),
                    "in_sample_spurious_per_stance": default["spurious_per_stance"],
                    "in_sample_stance_hit_rate": default.get("stance_hit_rate", float("nan")),
                    "held_out_fit_on": "walk",
                    "held_out_threshold": _threshold_repr(det_walk),
                    "held_out_spurious_per_stance": held["spurious_per_stance"],
                    "held_out_stance_hit_rate": held.get("stance_hit_rate", float("nan")),
                }
            )
    return rows


def _threshold_repr(det) -> str:
    if getattr(det, "threshold_rads_", None) is not None:
        return f"{np.degrees(det.threshold_rads_):.1f} deg/s"
    if getattr(det, "gamma_", None) is not None:
        return f"gamma {det.gamma_:.3g}"
    if getattr(det, "t_min_ms2_", None) is not None:
        return f"[{det.t_min_ms2_:.2f}, {det.t_max_ms2_:.2f}] m/s2"
    return ""


def synthetic_running_foot(
    n_strides: int = 40, *, stride_s: float = 0.70, contact_s: float = 0.24, foot_flat_s: float = 0.10, fs: float = 204.8, seed: int = 0
):
    """A SYNTHETIC foot-mounted running signal (no shared data set has running): a sanity check only.

    Each stride: heel strike (a 40 ms impact, gyro 250 deg/s, acc 3 g), foot flat for
    ``foot_flat_s`` (sensor noise only), push-off rising into the swing (sagittal rotation
    up to 700 deg/s, with the rotation reversal of the swing), for ``stride_s`` in all.
    Stride-to-stride timing varies by 3 %. Returns the recording and the true foot-flat
    intervals (samples).
    """
    from gaitml.consts import GRAVITY_MS2
    from gaitml.recording import Recording

    rng = np.random.default_rng(seed)
    w_parts, a_parts, flats, t0 = [], [], [], 0
    for _ in range(n_strides):
        k = 1.0 + rng.normal(0, 0.03)
        n_imp = int(round(0.04 * fs * k))
        n_flat = int(round(foot_flat_s * fs * k))
        n_push = int(round((contact_s - foot_flat_s - 0.04) * fs * k))
        n_sw = int(round((stride_s - contact_s) * fs * k))
        u = np.linspace(0, 1, n_imp, endpoint=False)
        imp = np.radians(250) * np.sin(np.pi * u)
        push = np.radians(400) * np.linspace(0, 1, n_push, endpoint=False) ** 2
        us = np.linspace(0, 1, n_sw, endpoint=False)
        sw = np.radians(400) * (1 - us) - np.radians(700) * np.sin(np.pi * us) ** 2 * (us > 0.25)
        w = np.concatenate([imp, np.zeros(n_flat), push, sw])
        a = np.concatenate(
            [3 * GRAVITY_MS2 * np.sin(np.pi * u), np.zeros(n_flat), 8 * np.linspace(0, 1, n_push), 15 * np.sin(2 * np.pi * us)]
        )
        flats.append((t0 + n_imp, t0 + n_imp + n_flat))
        w_parts.append(w)
        a_parts.append(a)
        t0 += len(w)
    w = np.concatenate(w_parts)
    a = np.concatenate(a_parts)
    gyr = np.column_stack([0.15 * w, w, 0.1 * w]) + rng.normal(0, np.radians(1.0), (len(w), 3))
    acc = np.column_stack([a, 0.3 * a, np.full_like(a, GRAVITY_MS2) + 0.5 * a]) + rng.normal(0, 0.05, (len(w), 3))
    rec = Recording(acc=acc, gyr=gyr, sampling_rate_hz=fs, meta={"id": "synthetic-running-foot"}, check_units=False)
    return rec, flats


def running_table(seeds=(0, 1, 2), foot_flats_s=(0.15, 0.10, 0.07)) -> list[dict]:
    """pseudo-std before/after (and eq. 8's tangent form) on the SYNTHETIC running signal: stance hit rate, spurious."""
    from gaitml.zupt import mask_runs

    variants = [
        ("per-sample rule, exact form (before)", {"merge_gap_s": 0.0, "min_interval_s": 0.0}),
        ("per-sample rule, tangent form eq. 8", {"merge_gap_s": 0.0, "min_interval_s": 0.0, "form": "tangent"}),
        ("interval rules, exact form (after)", {}),
    ]
    rows = []
    for ff in foot_flats_s:
        for label, params in variants:
            hit, spur, n = 0, 0, 0
            for seed in seeds:
                rec, flats = synthetic_running_foot(foot_flat_s=ff, seed=seed)
                s, e = mask_runs(get_detector("pseudo-std", **params).detect(rec).per_sample_zupts_)
                c = np.array([np.sum((s < b) & (e > a)) for a, b in flats])
                hit += int(np.sum(c > 0))
                n += len(flats)
                spur += max(0, len(s) - int(np.sum(c > 0)))
            rows.append({"foot_flat_s": ff, "variant": label, "n_stances": n, "stance_hit_rate": hit / n, "spurious_per_stance": spur / n})
    return rows


TRIAL_COLUMNS = [
    "trial",
    "foot",
    "reference",
    "variant",
    "n_stances",
    "n_intervals",
    "min_vel_hit_rate",
    "spurious_per_stance",
    "n_spurious",
    "stance_hit_rate",
    "proxy_spurious_per_stance",
    "proxy_stance_hit_rate",
]
HELDOUT_COLUMNS = [
    "detector",
    "test",
    "protocol",
    "in_sample_fit_on",
    "in_sample_threshold",
    "held_out_fit_on",
    "held_out_threshold",
    "in_sample_min_vel_hit_rate",
    "held_out_min_vel_hit_rate",
    "in_sample_spurious_per_stance",
    "held_out_spurious_per_stance",
    "in_sample_stance_hit_rate",
    "held_out_stance_hit_rate",
]
RUNNING_COLUMNS = ["foot_flat_s", "variant", "n_stances", "stance_hit_rate", "spurious_per_stance"]


def main(argv: list[str] | None = None) -> int:
    """Print the tables (markdown, or one JSON object with ``--json``)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.zupt_report", description=__doc__.splitlines()[0])
    ap.add_argument("--data", help="path of gaitmap's imu_sample.csv.gz (default: ../shared/data/gaitmap-example/)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--sensitivity", action="store_true", help="also the pseudo-std half-window sensitivity")
    ap.add_argument("--heldout", action="store_true", help="also the issue-13 tables: fitted thresholds held out, every trial, running")
    args = ap.parse_args(argv)
    rows = zupt_table(args.data)
    steps = step_count_table(args.data)
    sens = half_window_sensitivity(args.data) if args.sensitivity else []
    folder = Path(args.data).parent if args.data else None
    held = {"fit": heldout_fit_table(folder), "trials": trial_table(folder), "running_synthetic": running_table()} if args.heldout else {}
    if args.json:
        json.dump(
            {"zupt": rows, "steps": steps, "sensitivity": sens, **held},
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
    if held:
        print("\nFitted thresholds: in-sample beside held-out\n")
        print(format_markdown(held["fit"], HELDOUT_COLUMNS))
        print("\npseudo-std (paper threshold) before/after the interval rules, every trial\n")
        print(format_markdown(held["trials"], TRIAL_COLUMNS))
        print("\nSYNTHETIC running foot signal (no shared running data; sanity check only)\n")
        print(format_markdown(held["running_synthetic"], RUNNING_COLUMNS))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
