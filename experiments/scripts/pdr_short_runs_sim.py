"""The short-run rule (``gaitml pdr --short-runs``) on the simulated routes, where side steps and backward walking are real.

``python -m experiments.scripts.pdr_short_runs_sim [--model models/demo] [--seeds 10 ... 19] [--routes rectangle arc] [--demo-model DIR] [--csv FILE] [--out FILE]``
from the repository root. For every route and seed, :func:`gaitml.pipeline.pdr_routes.evaluate_route` runs the
variant "multi / model modes / hde" (the one of ``pdr_report`` and ``experiments/reports/pdr-step-modes.md``: the
route's own calibration, paper 003's ``single-peak`` steps) twice on the same simulated recording: with the rule off
(``short_run_windows=0``) and on (``short_run_windows=1``, :data:`gaitml.pdr.step_modes.SHORT_RUN_WINDOWS`). Per
route: the mean over the seeds of the per-step mode accuracy and of the end error (% of the distance), their
standard deviation and standard error (sd / sqrt(n)), and the mean paired change. ``--demo-model DIR`` (the model
``gaitml demo --out OUT`` trained, ``OUT/model``) adds ``make demo``'s own route: rectangle seed 11 with that model.

Adoption rule P3 (fixed before measuring, ``experiments/reports/tyrex-pdr.md``, pdrgate section): per route the
mean accuracy with the rule not lower, and the mean end error not higher, than without it by more than the standard
error over the seeds; the demo route's end error not above its value without the rule by more than the standard
deviation over the rectangle seeds of the end error without the rule.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["VARIANTS", "evaluate", "main", "summarise"]

#: (label, run_pdr keywords): the rule off and on
VARIANTS = (
    ("model modes, short runs off", {"modes": "model", "heading": "hde", "short_run_windows": 0.0}),
    ("model modes, short runs on", {"modes": "model", "heading": "hde", "short_run_windows": 1.0}),
)


def evaluate(routes, seeds, model) -> pd.DataFrame:
    """One row per route, seed and variant: ``mode_accuracy``, ``end_error_pct`` and the steps the rule moved."""
    from gaitml.pipeline.pdr_routes import evaluate_route

    rows = []
    t0 = time.perf_counter()
    for route in routes:
        for seed in seeds:
            for r in evaluate_route(route, seed, model=model, variants=VARIANTS, keep_results=True):
                res = r.pop("result")
                rows.append({**r, "short_run_steps": res.info.get("short_run_steps")})
            print(f"  {route} seed {seed} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return pd.DataFrame(rows)


def summarise(long: pd.DataFrame) -> pd.DataFrame:
    """Per route and variant: mean, sd and standard error over the seeds; the paired change (on - off)."""
    out = []
    for route, g in long.groupby("route", sort=False):
        piv = {m: g.pivot(index="seed", columns="variant", values=m) for m in ("mode_accuracy", "end_error_pct")}
        n = len(piv["mode_accuracy"])
        for label, _ in VARIANTS:
            row = {"route": route, "variant": label, "seeds": n}
            for m, p in piv.items():
                row[f"{m} mean"] = p[label].mean()
                row[f"{m} sd"] = p[label].std(ddof=1) if n > 1 else float("nan")
                row[f"{m} se"] = row[f"{m} sd"] / np.sqrt(n)
            row["steps moved (sum)"] = int(g[g["variant"] == label]["short_run_steps"].fillna(0).sum())
            out.append(row)
        off, on = VARIANTS[0][0], VARIANTS[1][0]
        out.append(
            {
                "route": route,
                "variant": "change (on - off)",
                "seeds": n,
                "mode_accuracy mean": (piv["mode_accuracy"][on] - piv["mode_accuracy"][off]).mean(),
                "end_error_pct mean": (piv["end_error_pct"][on] - piv["end_error_pct"][off]).mean(),
            }
        )
    return pd.DataFrame(out).set_index(["route", "variant"])


def verdicts(summary: pd.DataFrame, demo: pd.DataFrame | None) -> list[str]:
    """P3 of the adoption rule (module docstring)."""
    off, on = VARIANTS[0][0], VARIANTS[1][0]
    lines = []
    for route in dict.fromkeys(summary.index.get_level_values(0)):
        a, b = summary.loc[(route, off)], summary.loc[(route, on)]
        acc_ok = b["mode_accuracy mean"] >= a["mode_accuracy mean"] - a["mode_accuracy se"]
        err_ok = b["end_error_pct mean"] <= a["end_error_pct mean"] + a["end_error_pct se"]
        lines.append(
            f"P3b {route}: accuracy {a['mode_accuracy mean']:.4f} -> {b['mode_accuracy mean']:.4f} (se {a['mode_accuracy se']:.4f}) "
            f"{'ok' if acc_ok else 'WORSE'}; end error {a['end_error_pct mean']:.3f} -> {b['end_error_pct mean']:.3f} % "
            f"(se {a['end_error_pct se']:.3f}) {'ok' if err_ok else 'WORSE'}"
        )
    if demo is not None and ("rectangle", off) in summary.index:
        sd = summary.loc[("rectangle", off), "end_error_pct sd"]
        e = demo.set_index("variant")["end_error_pct"]
        ok = e[on] <= e[off] + sd
        lines.append(
            f"P3a demo route (rectangle seed 11, the demo's model): end error {e[off]:.2f} -> {e[on]:.2f} % (sd over the rectangle "
            f"seeds {sd:.2f}) {'ok' if ok else 'WORSE'}"
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.pdr_short_runs_sim", description=__doc__.split("\n")[0])
    p.add_argument("--model", default="models/demo", help="model of the seeds' runs (default models/demo)")
    p.add_argument("--seeds", type=int, nargs="+", default=list(range(10, 20)), help="route seeds (default 10-19, held out)")
    p.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
    p.add_argument("--demo-model", metavar="DIR", help="the model gaitml demo trained (OUT/model): adds make demo's route")
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per route, seed and variant)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    from experiments.scripts.tyrex_pdr import md
    from gaitml.models import load_model

    for d in filter(None, (args.model, args.demo_model)):
        if not (Path(d) / "model.json").is_file():
            raise SystemExit(f"error: {d} holds no model.json; pass a model folder (gaitml train / gaitml demo --out OUT: OUT/model).")
    t0 = time.perf_counter()
    long = evaluate(args.routes, args.seeds, load_model(args.model))
    demo = None
    if args.demo_model:
        demo = evaluate(["rectangle"], [11], load_model(args.demo_model))
        long = pd.concat([long, demo.assign(route="demo route (rectangle 11, demo model)")], ignore_index=True)
    if args.csv:
        long.to_csv(args.csv, index=False)
    seeds_only = long[~long["route"].str.startswith("demo")]
    summary = summarise(seeds_only)
    per_seed = long.pivot_table(index=["route", "seed"], columns="variant", values=["mode_accuracy", "end_error_pct", "short_run_steps"])
    per_seed.columns = [f"{m}: {v}" for m, v in per_seed.columns]
    lines = [
        f"### per route and seed ({args.model}; seeds {args.seeds[0]}-{args.seeds[-1]})",
        md(per_seed, "{:.4f}"),
        "",
        "### over the seeds",
        md(summary, "{:.4f}"),
        "",
        *verdicts(summary, demo),
        "",
    ]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
