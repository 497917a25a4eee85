"""Step detectors on the shared real recordings: per-recording tables and summaries (issue 4).

Runs every registered step detector on

- the IFSM flat-held phone files (paper 000, 284 / 319 true steps), and
- the 48 Oxford step counter optimisation recordings (hard floor and carpet
  reported separately, per carrying position),

and writes ``per_recording.csv`` (one row per detector and recording: counts,
count accuracy, precision / recall / F1 at the matching tolerance, timing
offset, period error), ``oxford_by_position.csv`` (mean per detector, surface
and position), ``summary.json`` and ``report.md`` into the output folder
(atomically). Credit: "Oxford step counter data set, Salvi et al." (CC BY 4.0).

Run: ``python -m gaitml.experiments.steps_real [--config experiments/steps-real.toml] [--out DIR]
[--detectors a,b] [--data DIR]`` (command-line options override the config).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import ConfigError
from gaitml.evaluation.steps import evaluate_steps
from gaitml.io import atomic_dir, read_recording
from gaitml.io.oxford import list_oxford_folders
from gaitml.steps import detector_names, get_detector

__all__ = ["run_steps_real", "evaluate_recording", "summarise_oxford", "load_steps_config", "main"]

TOLERANCE_S = 0.25
#: paper 000 Table 2 (true, AD-FSM, autocorrelation, IFSM) per IFSM file
PAPER_TABLE2 = {
    "acceleration_flat_holding_1": {"true": 284, "adfsm": 282, "autocorr": 279, "ifsm": 284},
    "acceleration_flat_holding_2": {"true": 319, "adfsm": 316, "autocorr": 316, "ifsm": 319},
}
#: paper 000 Table 3: manually read durations of the first 10 steps of file 1 (s)
PAPER_TABLE3_MANUAL_S = np.array([0.64, 0.56, 0.58, 0.50, 0.54, 0.50, 0.54, 0.52, 0.54, 0.50])
DEFAULT_DETECTORS = ("single-peak", "ifsm", "ifsm-literal", "adfsm", "autocorr", "fsm-selflearn", "adaptive", "zupt-magnitude")


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


DATA_SETS = ("ifsm-flat-phone", "oxford-step-counter")


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


def load_steps_config(path: str | Path) -> dict:
    """Read and validate ``experiments/steps-real.toml``; returns detectors, tolerance_s, data_dir, sets, name."""
    p = Path(path)
    try:
        raw = tomllib.loads(p.read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ConfigError(f"cannot read the steps config {p}: {exc}; fix the TOML.") from exc
    allowed = {"name", "detectors", "tolerance_s", "data"}
    extra = set(raw) - allowed
    if extra:
        raise ConfigError(f"unknown key(s) {sorted(extra)} in {p.name}; allowed: {sorted(allowed)}.")
    dets = raw.get("detectors", list(DEFAULT_DETECTORS))
    bad = [d for d in dets if d not in detector_names()]
    if bad:
        raise ConfigError(f"`detectors` has unknown name(s) {bad} in {p.name}; allowed: {', '.join(detector_names())}.")
    tol = raw.get("tolerance_s", TOLERANCE_S)
    if not isinstance(tol, int | float) or tol <= 0:
        raise ConfigError(f"`tolerance_s` must be a positive number in {p.name}, got {tol!r}.")
    data = raw.get("data", {})
    sets = data.get("sets", list(DATA_SETS))
    bad = [s for s in sets if s not in DATA_SETS]
    if bad:
        raise ConfigError(f"`data.sets` has unknown set(s) {bad} in {p.name}; allowed: {list(DATA_SETS)}.")
    data_dir = (p.parent / data["path"]).resolve() if "path" in data else None
    return {"name": raw.get("name", p.stem), "detectors": list(dets), "tolerance_s": float(tol), "data_dir": data_dir, "sets": list(sets)}


def run_steps_real(
    out_dir: str | Path,
    *,
    data_dir: str | Path,
    detectors=DEFAULT_DETECTORS,
    recordings=None,
    progress=None,
    tolerance_s: float = TOLERANCE_S,
    sets=DATA_SETS,
) -> dict:
    """Evaluate ``detectors`` on the shared step recordings and write the tables to ``out_dir``."""
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


def main(argv=None) -> int:
    """Command line: ``python -m gaitml.experiments.steps_real``."""
    root = Path(__file__).resolve().parents[2]
    p = argparse.ArgumentParser(prog="python -m gaitml.experiments.steps_real", description=__doc__.splitlines()[0])
    p.add_argument("--config", help="a steps TOML (experiments/steps-real.toml)")
    p.add_argument("--out", help="output folder (replaced atomically; default runs/<name>)")
    p.add_argument("--data", help="the shared data folder (default: the config's, else ../shared/data)")
    p.add_argument("--detectors", help="comma-separated detector names (default: the config's, else all)")
    a = p.parse_args(argv)
    try:
        cfg = (
            load_steps_config(a.config)
            if a.config
            else {
                "name": "steps-real",
                "detectors": list(DEFAULT_DETECTORS),
                "tolerance_s": TOLERANCE_S,
                "data_dir": None,
                "sets": list(DATA_SETS),
            }
        )
    except ConfigError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    dets = [d.strip() for d in a.detectors.split(",") if d.strip()] if a.detectors else cfg["detectors"]
    bad = [d for d in dets if d not in detector_names()]
    if bad:
        print(f"error: unknown detector(s) {bad}; valid: {', '.join(detector_names())}", file=sys.stderr)
        return 2
    data = Path(a.data) if a.data else (cfg["data_dir"] or root.parent / "shared" / "data")
    out = Path(a.out) if a.out else Path("runs") / cfg["name"]
    run_steps_real(
        out, data_dir=data, detectors=dets, tolerance_s=cfg["tolerance_s"], sets=cfg["sets"], progress=lambda m: print(m, file=sys.stderr)
    )
    print((out / "report.md").read_text())
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
