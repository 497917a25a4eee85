"""Step-synchronous windows against time windows: per-mode CV table and per-step PDR mode accuracy.

``python -m experiments.scripts.step_windows_report classify CONFIG [CONFIG ...]``
    Cross-validates each config twice, with ``windows.by = "time"`` and ``"steps"``
    (every other key as in the config, a ``[sweep]`` is ignored), and prints one
    markdown table per config: accuracy and macro-F1 before/after the adjacent-window
    correction, and per class recall ("accuracy of the mode") and F1 after it.

``python -m experiments.scripts.step_windows_report pdr CONFIG [--seeds 0 1 2] [--routes rectangle arc] [--models DIR]``
    Trains the config's model twice (time windows and step windows, the same
    simulated training data, ``train.cross_validate`` off), then runs the simulated
    PDR routes of :mod:`gaitml.pipeline.pdr_routes` with each: per-step mode
    accuracy (the majority true label over the detector's step span against the
    step's mode, as ``pdr_report`` scores it) and end-point error (% of distance).
    Per-step accuracy is given twice: as ``pdr_report`` scores it, and against the
    simulator's true steps (:func:`true_step_accuracy`; the two differ at mode changes).
    The time-window model is run with its default boundary refinement (``auto``) and
    with the nearest window (``nearest``); the step-window model has one prediction
    per step. Models are written to ``--models`` (default a temporary folder).

Measured tables: ``experiments/reports/step-windows.md``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["classify_table", "pdr_table", "main"]

WINDOW_BYS = ("time", "steps")


def _markdown(df: pd.DataFrame, fmt: str) -> str:
    """A DataFrame as a markdown table (index as the first column; tuple columns joined by ' ')."""
    cols = [" ".join(map(str, c)) if isinstance(c, tuple) else str(c) for c in df.columns]
    lines = ["| " + " | ".join([str(df.index.name or ""), *cols]) + " |", "|---" + "|---:" * len(cols) + "|"]
    for idx, row in df.iterrows():
        lines.append("| " + " | ".join([str(idx), *(format(v, fmt) if pd.notna(v) else "-" for v in row)]) + " |")
    return "\n".join(lines)


def _point(cfg, by: str):
    import dataclasses

    c = cfg.with_values({"windows.by": by})
    return dataclasses.replace(c, sweep={})


def classify_table(config: str, data: str | None = None) -> tuple[pd.DataFrame, dict]:
    """Per-mode recall/F1 and headline scores of ``config`` with time and step windows (``data``: a folder config's data folder)."""
    from gaitml.pipeline import evaluate_config, load_config

    cfg = load_config(config, check_paths=data is None)
    if data is not None:
        cfg = cfg.with_data_path(data)
    rows, head = [], {}
    for by in WINDOW_BYS:
        t0 = time.perf_counter()
        res = evaluate_config(_point(cfg, by), progress=False, write=False)
        head[by] = {
            "accuracy_before": res["accuracy_before_correction"],
            "accuracy_after": res["accuracy_after_correction"],
            "macro_f1_before": res["macro_f1_before_correction"],
            "macro_f1_after": res["macro_f1_after_correction"],
            "n_windows": res["n_windows"],
            "n_dropped_label_fraction": res["n_dropped_label_fraction"],
            "seconds": round(time.perf_counter() - t0, 1),
        }
        for label, pc in res["per_class"].items():
            rows.append({"by": by, "label": label, "recall": pc["recall"], "f1": pc["f1"], "support": pc["support"]})
        print(f"  {cfg.name} by {by}: done in {head[by]['seconds']} s", file=sys.stderr)
    return pd.DataFrame(rows), head


def _classify_markdown(name: str, per: pd.DataFrame, head: dict) -> str:
    out = [f"### {name}", "", "| | time windows (1.5 s) | step windows |", "|---|---:|---:|"]
    for key, text in (
        ("accuracy_before", "accuracy before correction"),
        ("accuracy_after", "accuracy after correction"),
        ("macro_f1_before", "macro-F1 before correction"),
        ("macro_f1_after", "macro-F1 after correction"),
    ):
        out.append(f"| {text} | {head['time'][key]:.4f} | {head['steps'][key]:.4f} |")
    out.append(
        f"| windows (dropped: weak majority) | {head['time']['n_windows']} ({head['time']['n_dropped_label_fraction']}) "
        f"| {head['steps']['n_windows']} ({head['steps']['n_dropped_label_fraction']}) |"
    )
    out += ["", "| label | recall time | recall steps | F1 time | F1 steps |", "|---|---:|---:|---:|---:|"]
    for label in dict.fromkeys(per["label"]):
        t = per[(per["label"] == label) & (per["by"] == "time")]
        s = per[(per["label"] == label) & (per["by"] == "steps")]

        def v(df, c):
            return f"{float(df[c].iloc[0]):.4f}" if len(df) else "-"

        out.append(f"| {label} | {v(t, 'recall')} | {v(s, 'recall')} | {v(t, 'f1')} | {v(s, 'f1')} |")
    return "\n".join(out) + "\n"


def pdr_table(config: str, seeds, routes, models_dir: Path) -> pd.DataFrame:
    """One row per route, seed and model variant: per-step mode accuracy and end-point error."""
    from gaitml.pipeline import load_config, train_config
    from gaitml.pipeline.pdr_routes import evaluate_route

    cfg = load_config(config)
    models = {}
    for by in WINDOW_BYS:
        t0 = time.perf_counter()
        c = _point(cfg, by).with_values({"train.cross_validate": False})
        models[by] = train_config(c, out_dir=models_dir / f"{cfg.name}-{by}", progress=False)
        print(
            f"  trained {by} model in {time.perf_counter() - t0:.0f} s ({models[by].info['training_data']['n_windows']} windows)",
            file=sys.stderr,
        )
    variants_time = (
        ("time windows, refined boundaries", {"modes": "model", "heading": "hde"}),
        ("time windows, nearest window", {"modes": "model", "heading": "hde", "mode_boundaries": "nearest"}),
    )
    variants_steps = (("step windows, one prediction per step", {"modes": "model", "heading": "hde"}),)
    from gaitml.simulate import simulate_route

    rows = []
    for route in routes:
        for seed in seeds:
            ref = simulate_route(route, seed=seed).reference["steps"]  # the walk evaluate_route simulates (same seed)
            for model, variants in ((models["time"], variants_time), (models["steps"], variants_steps)):
                for row in evaluate_route(route, seed, model=model, variants=variants, keep_results=True):
                    row["mode_accuracy_true_steps"] = true_step_accuracy(row.pop("result").steps, ref)
                    rows.append(row)
            print(f"  {route} seed {seed} done", file=sys.stderr)
    return pd.DataFrame(rows)


def true_step_accuracy(steps: pd.DataFrame, ref: pd.DataFrame) -> float:
    """Share of detected steps whose mode is the mode of the nearest true step of the simulator.

    The simulator's step table (``reference['steps']``: ``t_s`` the step event, ``mode``)
    says in which mode each step was made; every detected step is matched to the true
    step nearest its peak time. ``pdr_report``'s score instead takes the majority
    per-sample label over the detector's step span, which for single-peak reaches
    past the peak (the simulator's labels change right after a step's event), so the
    last step before each mode change counts as the next mode there.
    """
    t = steps["t_peak_s"].to_numpy(float)
    rt = ref["t_s"].to_numpy(float)
    j = np.abs(t[:, None] - rt[None, :]).argmin(axis=1)
    return float(np.mean(steps["mode"].to_numpy().astype(str) == ref["mode"].to_numpy().astype(str)[j]))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.step_windows_report", description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="what", required=True)
    c = sub.add_parser("classify")
    c.add_argument("configs", nargs="+")
    c.add_argument("--data", metavar="DIR", help="data folder of a folder config (as gaitml evaluate --data); one config only")
    q = sub.add_parser("pdr")
    q.add_argument("config")
    q.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    q.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
    q.add_argument("--models", metavar="DIR", help="where to write the two trained models (default: a temporary folder)")
    args = p.parse_args(argv)
    if args.what == "classify":
        for config in args.configs:
            per, head = classify_table(config, args.data)
            print(_classify_markdown(Path(config).stem, per, head))
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        long = pdr_table(args.config, args.seeds, args.routes, Path(args.models) if args.models else Path(tmp))
    acc = long.pivot_table(index="variant", columns="route", values="mode_accuracy", aggfunc="mean")
    err = long.pivot_table(index="variant", columns="route", values="end_error_pct", aggfunc="mean")
    per_seed = long.pivot_table(index="variant", columns=["route", "seed"], values="mode_accuracy")
    print(f"per-step mode accuracy, mean over seeds {args.seeds}:")
    print(_markdown(acc, ".3f"))
    print("\nper seed:")
    print(_markdown(per_seed, ".3f"))
    print(f"\nend-point error (% of distance), mean over seeds {args.seeds}:")
    print(_markdown(err, ".2f"))
    acc2 = long.pivot_table(index="variant", columns="route", values="mode_accuracy_true_steps", aggfunc="mean")
    print(f"\nper-step mode accuracy against the simulator's true steps (nearest true step's mode), mean over seeds {args.seeds}:")
    print(_markdown(acc2, ".3f"))
    print("\nper seed:")
    print(_markdown(long.pivot_table(index="variant", columns=["route", "seed"], values="mode_accuracy_true_steps"), ".3f"))
    n = long.groupby("variant")[["mode_accuracy", "mode_accuracy_true_steps"]].mean()
    print("\nper-step mode accuracy over all routes and seeds (pdr_report scoring; true steps):")
    print(_markdown(n, ".3f"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
