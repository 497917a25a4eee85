"""Step detectors on the shared real recordings: the ``task = "steps"`` experiment.

Runs every step detector a config lists on

- the IFSM flat-held phone files (paper 000, 284 / 319 true steps), and
- the 48 Oxford step counter optimisation recordings (hard floor and carpet
  reported separately, per carrying position),

and writes ``per_recording.csv`` (one row per detector and recording: counts,
count accuracy, precision / recall / F1 at the matching tolerance, timing
offset, period error), ``oxford_by_position.csv`` (mean per detector, surface
and position), ``summary.json`` and ``report.md`` into the output folder
(atomically). Credit: "Oxford step counter data set, Salvi et al." (CC BY 4.0).

Run: ``gaitml evaluate experiments/steps-real.toml [--out DIR] [--data DIR]`` (the
config's keys: :mod:`gaitml.experiments.config`).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.evaluation.steps import evaluate_steps
from gaitml.experiments.config import STEP_DATA_SETS, STEP_TOLERANCE_S, ExperimentConfig
from gaitml.io import atomic_dir, read_recording
from gaitml.io.oxford import list_oxford_folders
from gaitml.steps import detector_names, get_detector

__all__ = ["run_steps_real", "evaluate_recording", "evaluate_steps_config", "summarise_oxford", "load_recordings"]

TOLERANCE_S = STEP_TOLERANCE_S
#: paper 000 Table 2 (true, AD-FSM, autocorrelation, IFSM) per IFSM file
PAPER_TABLE2 = {
    "acceleration_flat_holding_1": {"true": 284, "adfsm": 282, "autocorr": 279, "ifsm": 284},
    "acceleration_flat_holding_2": {"true": 319, "adfsm": 316, "autocorr": 316, "ifsm": 319},
}
#: paper 000 Table 3: manually read durations of the first 10 steps of file 1 (s)
PAPER_TABLE3_MANUAL_S = np.array([0.64, 0.56, 0.58, 0.50, 0.54, 0.50, 0.54, 0.52, 0.54, 0.50])


def evaluate_recording(rec, detector: str, *, tolerance_s: float = TOLERANCE_S) -> dict:
    """Detect steps in ``rec`` with ``detector`` and evaluate against its reference."""
    t = time.perf_counter()
    steps = get_detector(detector).detect(rec).steps_
    dt = time.perf_counter() - t
    ref = rec.reference
    true_s = ref.get("steps_t_s")
    ev = evaluate_steps(steps, None if true_s is None else np.asarray(true_s), tolerance_s=tolerance_s, n_true=ref.get("n_steps_true"))
    row = {
        "detector": detector,
        "recording": rec.name,
        "dataset": rec.meta.get("format"),
        "surface": rec.meta.get("surface", ""),
        "position": rec.meta.get("position", ""),
        "subject": rec.meta.get("subject", ""),
        "device": rec.meta.get("device", ""),
        "duration_s": rec.duration_s,
        "seconds": dt,
        **{k: v for k, v in ev.items() if k != "tolerance_s"},
    }
    if detector == "ifsm" and rec.name == "acceleration_flat_holding_1" and len(steps) >= 10:
        row["first10_period_mad_s"] = float(np.abs(steps["period_s"].to_numpy()[:10] - PAPER_TABLE3_MANUAL_S).mean())
    return row


def summarise_oxford(table: pd.DataFrame) -> pd.DataFrame:
    """Mean count accuracy and F1 per detector, surface and position (plus an 'ALL' row per surface)."""
    ox = table[table["dataset"] == "oxford"]
    if ox.empty:
        return pd.DataFrame()
    g = ox.groupby(["detector", "surface", "position"]).agg(
        n_recordings=("recording", "size"),
        count_accuracy=("count_accuracy", "mean"),
        f1=("f1", "mean"),
        timing_offset_s=("timing_offset_s", "mean"),
    )
    # the 'ALL' row: the mean over positions (each position weighted equally) and the worst position
    allr = g.groupby(level=["detector", "surface"]).agg(
        n_recordings=("n_recordings", "sum"),
        count_accuracy=("count_accuracy", "mean"),
        f1=("f1", "mean"),
        timing_offset_s=("timing_offset_s", "mean"),
    )
    allr["worst_position_count_accuracy"] = g.groupby(level=["detector", "surface"])["count_accuracy"].min()
    allr["mean_over_recordings_count_accuracy"] = ox.groupby(["detector", "surface"])["count_accuracy"].mean()
    allr = allr.reset_index()
    allr["position"] = "ALL"
    return pd.concat([g.reset_index(), allr], ignore_index=True).sort_values(["detector", "surface", "position"]).reset_index(drop=True)


def _fmt(x, pct=False):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    return f"{100 * x:.2f}" if pct else f"{x:.3f}"


def _report(table: pd.DataFrame, by_pos: pd.DataFrame, tolerance_s: float = TOLERANCE_S) -> str:
    lines = [
        "# Step detectors on the shared real recordings",
        "",
        f"Matching tolerance {tolerance_s} s. Count accuracy = 1 - |n_det - n_true| / n_true.",
        "",
    ]
    ifsm = table[table["dataset"] == "ifsm-xlsx"]
    if not ifsm.empty:
        lines += [
            "## IFSM flat-held phone data (paper 000)",
            "",
            "| detector | file 1 (284) | file 2 (319) | paper file 1 | paper file 2 |",
            "|---|---|---|---|---|",
        ]
        for det, g in ifsm.groupby("detector", sort=False):
            n = dict(zip(g["recording"], g["n_detected"], strict=True))
            p1 = PAPER_TABLE2["acceleration_flat_holding_1"].get(det, "")
            p2 = PAPER_TABLE2["acceleration_flat_holding_2"].get(det, "")
            lines.append(
                f"| {det} | {n.get('acceleration_flat_holding_1', '-')} | {n.get('acceleration_flat_holding_2', '-')} | {p1} | {p2} |"
            )
        mad = ifsm.get("first10_period_mad_s")
        if mad is not None and mad.notna().any():
            lines += [
                "",
                f"ifsm periods of the first 10 steps of file 1 vs the manual durations of Table 3: mean |diff| = {mad.dropna().iloc[0]:.3f} s",
            ]
        lines.append("")
    if not by_pos.empty:
        lines += ["## Oxford step counter, optimisation set (Salvi et al., CC BY 4.0)", ""]
        for surface, gs in by_pos.groupby("surface"):
            lines += [f"### {surface}", ""]
            positions = sorted(p for p in gs["position"].unique() if p != "ALL") + ["ALL"]
            lines += ["| detector | " + " | ".join(positions) + " | worst |", "|---" * (len(positions) + 2) + "|"]
            for det, gd in gs.groupby("detector", sort=False):
                acc = dict(zip(gd["position"], gd["count_accuracy"], strict=True))
                f1 = dict(zip(gd["position"], gd["f1"], strict=True))
                worst = gd.loc[gd["position"] == "ALL", "worst_position_count_accuracy"]
                cells = [f"{_fmt(acc.get(p), True)} / {_fmt(f1.get(p))}" for p in positions]
                lines.append(f"| {det} | " + " | ".join(cells) + f" | {_fmt(worst.iloc[0] if len(worst) else None, True)} |")
            lines += ["", "cells: mean count accuracy (%) / mean F1; ALL = mean over positions.", ""]
    return "\n".join(lines) + "\n"


DATA_SETS = STEP_DATA_SETS


def load_recordings(data_dir: Path, sets=DATA_SETS) -> list:
    """The IFSM files and the Oxford optimisation folders under ``data_dir`` (missing sets are skipped)."""
    recs = []
    ifsm_dir = data_dir / "ifsm-flat-phone"
    if "ifsm-flat-phone" in sets and ifsm_dir.is_dir():
        recs.extend(read_recording(f) for f in sorted(ifsm_dir.glob("*.xlsx")))
    ox = data_dir / "oxford-step-counter" / "optimisation"
    if "oxford-step-counter" in sets and ox.is_dir():
        recs.extend(read_recording(d) for d in list_oxford_folders(ox))
    return recs


def run_steps_real(
    out_dir: str | Path,
    *,
    data_dir: str | Path,
    detectors=None,
    recordings=None,
    progress=None,
    tolerance_s: float = TOLERANCE_S,
    sets=DATA_SETS,
) -> dict:
    """Evaluate ``detectors`` (default: every registered one) on the shared step recordings and write the tables to ``out_dir``."""
    detectors = detector_names() if detectors is None else detectors
    recs = recordings if recordings is not None else load_recordings(Path(data_dir), sets)
    rows = []
    for det in detectors:
        for rec in recs:
            rows.append(evaluate_recording(rec, det, tolerance_s=tolerance_s))
        if progress:
            progress(f"{det}: done")
    table = pd.DataFrame(rows)
    by_pos = summarise_oxford(table)
    summary = {"tolerance_s": tolerance_s, "ifsm": {}, "oxford": {}}
    for _, r in table[table["dataset"] == "ifsm-xlsx"].iterrows():
        summary["ifsm"].setdefault(r["detector"], {})[r["recording"]] = {
            "n_detected": int(r["n_detected"]),
            "n_true": int(r["n_true"]),
            "count_accuracy": float(r["count_accuracy"]),
        }
    if "first10_period_mad_s" in table:
        v = table["first10_period_mad_s"].dropna()
        if len(v):
            summary["ifsm_first10_period_mad_s"] = float(v.iloc[0])
    if not by_pos.empty:
        for _, r in by_pos[by_pos["position"] == "ALL"].iterrows():
            summary["oxford"].setdefault(r["detector"], {})[r["surface"]] = {
                "mean_count_accuracy": float(r["count_accuracy"]),
                "mean_f1": float(r["f1"]),
                "worst_position_count_accuracy": float(r["worst_position_count_accuracy"]),
            }
    out = Path(out_dir)
    with atomic_dir(out) as tmp:
        tmp = Path(tmp)
        table.to_csv(tmp / "per_recording.csv", index=False)
        by_pos.to_csv(tmp / "oxford_by_position.csv", index=False)
        (tmp / "summary.json").write_text(json.dumps(summary, indent=2))
        (tmp / "report.md").write_text(_report(table, by_pos, tolerance_s))
    return summary


def evaluate_steps_config(cfg: ExperimentConfig, *, out_dir: str | Path | None = None, progress=None) -> dict:
    """Run a ``task = "steps"`` config and write its run folder.

    Parameters
    ----------
    cfg : ExperimentConfig
        A validated config with ``task = "steps"``.
    out_dir : path, optional
        The run folder (replaced atomically); default ``runs/<name>/<UTC timestamp>/``.
    progress : bool or callable, optional
        Called with one line per finished detector (``True``: printed on stderr).

    Returns
    -------
    dict
        The summary written to ``summary.json`` plus ``name``, ``task`` and ``run_dir``.
    """
    from gaitml.experiments.runner import default_run_dir

    out = Path(out_dir) if out_dir is not None else default_run_dir(cfg)
    if progress is True:
        progress = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
    s = cfg["steps"]
    summary = run_steps_real(
        out, data_dir=cfg.data_path, detectors=s["detectors"], tolerance_s=s["tolerance_s"], sets=cfg["data"]["sets"], progress=progress
    )
    return {"name": cfg.name, "task": cfg.task, **summary, "run_dir": str(out)}
