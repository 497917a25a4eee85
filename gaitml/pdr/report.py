"""End-point error table of paper 003 sec. 4.3 on simulated mixed-mode routes.

``python -m gaitml.pdr.report [--model MODEL_DIR] [--seeds 0 1 2] [--plot PNG] [--csv FILE]``

For each route (rectangle ~262 m, arc ~400 m) and seed: the simulated walk of
:func:`gaitml.simulate.simulate_route` (mixed modes, returns to the start); a separate
calibration recording of the same subject (150 s of mixed modes on a straight route,
another seed) fits the step length model per mode and the DW-PCA polarity
(:func:`gaitml.pdr.calibrate.calibrate_from_reference`). The initial heading is the true
one (a compass would give it; the closure error of a closed route does not depend on it).
Then the variants:

- ``multi / true modes / hde``: multi-state update, per-step modes from the labels.
- ``multi / model modes / hde``: modes from the model's window predictions (``--model``),
  mode changes re-placed step by step (:mod:`gaitml.pdr.step_modes`).
- ``multi / model modes / hde / nearest window``: the same without that refinement (each
  step takes the mode of the nearest corrected window, paper 003 as written).
- ``multi / model modes / hde / window at step middle``: the window nearest the middle
  between the step peak and the next one.
- ``forward-only / hde``: traditional PDR, every step a walk step (paper 003's baseline).
- ``multi / true modes / gyro``, ``dwpca``, ``dwpca-hde``: other heading sources.
- ``multi / true modes / hde / true lengths``: the step lengths of the reference (isolates
  heading and mode effects from step length).
- ``multi / true modes / paper HDE (no drift fit)``: buffered HDE without the drift-rate fit.
- ``multi / true modes / gyro / true gyro bias removed``: the simulator's gyro bias (in
  ``meta``) subtracted: what the heading error is made of.

The error is |estimated end - true end| / true distance (the true end is the start).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import pandas as pd

from gaitml.evaluation.trajectory import end_point_error, path_length
from gaitml.pdr.calibrate import calibrate_from_reference
from gaitml.pdr.hde import HeuristicDriftElimination
from gaitml.pdr.pipeline import modes_from_labels, run_pdr

__all__ = ["VARIANTS", "evaluate_route", "main", "route_table"]

#: (label, run_pdr keyword arguments); "model" variants need a model.
VARIANTS = (
    ("multi / true modes / hde", {"modes": "true", "heading": "hde"}),
    ("multi / model modes / hde", {"modes": "model", "heading": "hde"}),
    ("multi / model modes / hde / nearest window", {"modes": "model", "heading": "hde", "mode_boundaries": "nearest"}),
    ("multi / model modes / hde / window at step middle", {"modes": "model", "heading": "hde", "mode_boundaries": "middle"}),
    ("forward-only / hde", {"modes": "forward", "heading": "hde"}),
    ("forward-only / gyro", {"modes": "forward", "heading": "gyro"}),
    ("multi / true modes / gyro", {"modes": "true", "heading": "gyro"}),
    ("multi / true modes / dwpca", {"modes": "true", "heading": "dwpca"}),
    ("multi / true modes / dwpca-hde", {"modes": "true", "heading": "dwpca-hde"}),
    ("multi / true modes / hde / true lengths", {"modes": "true", "heading": "hde", "step_length": "reference"}),
    (
        "multi / true modes / paper HDE (no drift fit)",
        {"modes": "true", "heading": "hde", "hde_kwargs": {"drift_rate": "none", "max_error_rad": np.pi}},
    ),
    ("multi / true modes / gyro / true gyro bias removed", {"modes": "true", "heading": "gyro", "remove_true_gyro_bias": True}),
)
CALIBRATION_S = 150.0


def evaluate_route(route: str, seed: int, *, model=None, variants=VARIANTS, keep_results: bool = False) -> list[dict]:
    """Run every variant on one simulated route; one dict per variant."""
    from gaitml.simulate import sample_subjects, simulate_recording, simulate_route

    rec = simulate_route(route, seed=seed)
    subject = sample_subjects(1, seed)[0]  # the subject simulate_route draws for this seed
    cal_rec = simulate_recording(subject, route="straight", duration_s=CALIBRATION_S, seed=(seed, 4242))
    cal = calibrate_from_reference(cal_rec)
    truth = rec.reference["trajectory"]
    xy_true = truth[["x_m", "y_m"]].to_numpy(float)
    dist = path_length(xy_true)
    h0 = float(truth["heading_rad"].iloc[0])
    rows = []
    for label, kw in variants:
        if kw.get("modes") == "model" and model is None:
            continue
        kw = dict(kw)
        kw.setdefault("step_length", cal.step_length)
        hde_kwargs = kw.pop("hde_kwargs", {})
        r = rec
        if kw.pop("remove_true_gyro_bias", False):
            bias = np.array([rec.meta.get(f"gyr_bias_{a}_rads", 0.0) for a in "xyz"], dtype=float)
            r = rec.replace(gyr=rec.gyr - bias)
        res = run_pdr(
            r, model=model, initial_heading_rad=h0, dwpca=cal.dwpca, hde=HeuristicDriftElimination(reference_rad=h0, **hde_kwargs), **kw
        )
        err, pct = end_point_error(res.trajectory[["x_m", "y_m"]].to_numpy(), xy_true[-1], dist)
        row = {
            "route": route,
            "seed": seed,
            "variant": label,
            "distance_true_m": dist,
            "distance_est_m": res.distance_m,
            "n_steps": res.n_steps,
            "n_steps_true": int(rec.reference.get("n_steps_true", len(rec.reference["steps"]))),
            "end_error_m": err,
            "end_error_pct": pct,
        }
        if kw.get("modes") == "model":
            start = res.steps["start"].to_numpy()
            true_modes = modes_from_labels(rec.labels, start, np.maximum(res.steps["end"].to_numpy(), start + 1))
            row["mode_accuracy"] = float(np.mean(true_modes == res.steps["mode"].to_numpy()))
        if keep_results:
            row["result"] = res
        rows.append(row)
    return rows


def route_table(rows: list[dict]) -> pd.DataFrame:
    """Pivot: one row per variant, columns route/seed end-point errors (%) and per-route means."""
    df = pd.DataFrame([{k: v for k, v in r.items() if k != "result"} for r in rows])
    order = list(dict.fromkeys(df["variant"]))
    tab = df.pivot_table(index="variant", columns=["route", "seed"], values="end_error_pct").reindex(order)
    for route in dict.fromkeys(df["route"]):
        tab[(route, "mean")] = tab[route].mean(axis=1)
        tab[(route, "max")] = tab[route].drop(columns=["mean"], errors="ignore").max(axis=1)
    # seeds in numeric order, then max and mean, per route
    return tab[sorted(tab.columns, key=lambda c: (c[0], 1, c[1], 0) if isinstance(c[1], str) else (c[0], 0, "", c[1]))]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m gaitml.pdr.report", description=__doc__.split("\n")[0])
    p.add_argument("--model", metavar="MODEL_DIR", help="model for the 'model modes' rows (default: models/demo if present)")
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
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
            rows += evaluate_route(route, seed, model=model, keep_results=bool(args.plot))
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
