"""End-point error table of paper 003 sec. 4.3 on simulated mixed-mode routes.

``python -m experiments.scripts.pdr_report [--model MODEL_DIR] [--seeds 0 1 2] [--detector NAME] [--plot PNG] [--csv FILE]``
from the repository root. The routes, calibration and variants are described in
:mod:`gaitml.pipeline.pdr_routes`; measured tables: ``experiments/scripts/README.md``.
"""

from __future__ import annotations

import argparse
import sys
import time

import pandas as pd

from gaitml.pipeline.pdr_routes import evaluate_route, route_table

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.pdr_report", description=__doc__.split("\n")[0])
    p.add_argument("--model", metavar="MODEL_DIR", help="model for the 'model modes' rows (default: models/demo if present)")
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
    p.add_argument(
        "--detector",
        default="single-peak",
        help="step detector of every variant (default single-peak, paper 003; adaptive finds the steps of calm walkers)",
    )
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per route/seed/variant)")
    p.add_argument("--plot", metavar="PNG", help="trajectory plot of the first route/seed (truth, multi-state, forward-only)")
    args = p.parse_args(argv)
    from pathlib import Path

    model = None
    mdir = args.model or ("models/demo" if Path("models/demo/model.json").is_file() else None)
    if mdir:
        from gaitml.models import load_model

        model = load_model(mdir)
        print(f"model: {mdir} ({model.kind}, labels {', '.join(model.labels)})", file=sys.stderr)
    else:
        print("no model given and models/demo missing: the 'model modes' rows are skipped", file=sys.stderr)
    rows = []
    t0 = time.perf_counter()
    for route in args.routes:
        for seed in args.seeds:
            rows += evaluate_route(route, seed, model=model, keep_results=bool(args.plot), detector=args.detector)
            print(f"  {route} seed {seed} done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    tab = route_table(rows)
    with pd.option_context("display.width", 200, "display.max_columns", 30, "display.float_format", "{:.2f}".format):
        print(
            "end-point error, % of distance travelled (paper 003: multi-state 1.60 % rectangle / 1.30 % arc; traditional 12.14 % / 15.42 %)"
        )
        print(tab)
        long = pd.DataFrame([{k: v for k, v in r.items() if k != "result"} for r in rows])
        extra = long.groupby("route")[["distance_true_m", "n_steps", "n_steps_true"]].mean()
        print(extra.round(1))
        if "mode_accuracy" in long:
            acc = long.dropna(subset=["mode_accuracy"]).pivot_table(index="variant", columns="route", values="mode_accuracy")
            print("per-step mode accuracy of the model (mean over seeds):")
            print(acc.to_string(float_format="{:.3f}".format))
    if args.csv:
        from gaitml.io import write_csv

        write_csv(args.csv, pd.DataFrame([{k: v for k, v in r.items() if k != "result"} for r in rows]))
    if args.plot:
        from gaitml.pdr.plot import plot_trajectory
        from gaitml.simulate import simulate_route

        first = [r for r in rows if r["route"] == args.routes[0] and r["seed"] == args.seeds[0]]
        preferred = [r for r in first if r["variant"].startswith("multi / model")] or [
            r for r in first if r["variant"] == "multi / true modes / hde"
        ]
        main_row = preferred[0]
        others = {
            f"{r['variant']} ({r['end_error_pct']:.2f} %)": r["result"].trajectory
            for r in first
            if r["variant"] in ("forward-only / hde", "multi / true modes / hde", "multi / true modes / gyro") and r is not main_row
        }
        truth = simulate_route(args.routes[0], seed=args.seeds[0]).reference["trajectory"]
        title = f"{args.routes[0]} seed {args.seeds[0]}: {main_row['variant']} end error {main_row['end_error_pct']:.2f} % of {main_row['distance_true_m']:.0f} m"
        plot_trajectory(args.plot, main_row["result"].trajectory, truth=truth, others=others, title=title)
        print(f"plot written to {args.plot}", file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
