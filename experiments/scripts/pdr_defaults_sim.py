"""The PDR defaults against paper 003's settings on the simulator's routes (issue 27: the defaults must not get worse there).

``python -m experiments.scripts.pdr_defaults_sim [--routes rectangle arc] [--seeds 0 1 2 11] [--model models/demo] [--csv FILE]
[--step-length FILE] [--no-demo]``
from the repository root. For every simulated route (:func:`gaitml.simulate.simulate_route`)
it dead-reckons with :func:`gaitml.pdr.run_pdr` two ways a user would:

- ``cli``: as ``gaitml pdr`` without ``--step-length`` (uncalibrated step length, forward-only,
  start heading from the reference), the defaults against ``--detector single-peak --heading
  hde --gyro-bias off --hde-guard off`` (paper 003, the defaults before issue 27);
- ``demo``: as ``make demo``'s PDR (:func:`gaitml.pipeline.pdr_routes.evaluate_route`: step
  length calibrated on a straight walk of the same simulated subject, HDE, model modes with
  ``--model``, forward-only), with the gyroscope bias removed or not and each detector.

``--step-length FILE`` gives the ``cli`` rows that step length model (as ``gaitml pdr --step-length``: e.g. a
candidate for the uncalibrated default); ``--no-demo`` leaves out the ``demo`` rows (their length is calibrated).
It prints the end-point error in % of the distance per route and seed, and the median.
Nothing is fitted on these routes: the seeds give the spread.
"""

from __future__ import annotations

import argparse
import sys
import time

import pandas as pd

__all__ = ["main"]

PAPER003 = {"detector": "single-peak", "heading": "hde", "gyro_bias": "off", "hde_guard": "off"}


def cli_rows(route: str, seed: int, step_length=None) -> list[dict]:
    from experiments.scripts.tyrex_pdr import pdr_kwargs
    from gaitml.evaluation.trajectory import end_point_error, path_length
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    rec = simulate_route(route, seed=seed)
    truth = rec.reference["trajectory"]
    xy = truth[["x_m", "y_m"]].to_numpy(float)
    dist = path_length(xy)
    h0 = float(truth["heading_rad"].iloc[0])
    rows = []
    for name, kw in (
        ("cli defaults", {}),
        ("cli adaptive/gyro/bias auto", {"detector": "adaptive", "heading": "gyro", "gyro_bias": "auto"}),
        ("cli adaptive/hde/bias auto", {"detector": "adaptive", "heading": "hde", "gyro_bias": "auto"}),
        ("cli adaptive/hde/bias off", {"detector": "adaptive", "heading": "hde", "gyro_bias": "off"}),
        ("cli single-peak/hde/bias auto", {"detector": "single-peak", "heading": "hde", "gyro_bias": "auto"}),
        ("cli paper003", PAPER003),
    ):
        res = run_pdr(rec, modes="forward", initial_heading_rad=h0, step_length=step_length, **pdr_kwargs(kw, h0))
        _, pct = end_point_error(res.trajectory[["x_m", "y_m"]].to_numpy(), xy[-1], dist)
        rows.append({"route": route, "seed": seed, "variant": name, "end_error_pct": pct, "distance_ratio": res.distance_m / dist})
    return rows


def demo_rows(route: str, seed: int, model) -> list[dict]:
    from gaitml.pipeline.pdr_routes import evaluate_route

    variants = []
    for det in ("single-peak", "adaptive"):
        for bias in ("off", "auto"):
            variants.append(
                (f"demo forward-only/hde {det} bias {bias}", {"modes": "forward", "heading": "hde", "detector": det, "gyro_bias": bias})
            )
            if model is not None:
                variants.append(
                    (f"demo model/hde {det} bias {bias}", {"modes": "model", "heading": "hde", "detector": det, "gyro_bias": bias})
                )
    out = evaluate_route(route, seed, model=model, variants=tuple(variants))
    return [
        {
            "route": route,
            "seed": seed,
            "variant": r["variant"],
            "end_error_pct": r["end_error_pct"],
            "distance_ratio": r["distance_est_m"] / r["distance_true_m"],
        }
        for r in out
    ]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.pdr_defaults_sim", description=__doc__.split("\n")[0])
    p.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 11])
    p.add_argument("--model", default="models/demo", help="model for the demo's model-mode rows ('' to skip)")
    p.add_argument("--csv", metavar="FILE")
    p.add_argument("--step-length", metavar="FILE", help="step length model JSON for the cli rows (default: the uncalibrated one)")
    p.add_argument("--no-demo", action="store_true", help="leave out the demo rows")
    args = p.parse_args(argv)
    step_length = None
    if args.step_length:
        from gaitml.pdr.step_length import StepLengthModel

        step_length = StepLengthModel.load(args.step_length)
    model = None
    if args.model:
        from gaitml.models import load_model

        model = load_model(args.model)
    t0 = time.perf_counter()
    rows = []
    for route in args.routes:
        for seed in args.seeds:
            rows += cli_rows(route, seed, step_length)
            if not args.no_demo:
                rows += demo_rows(route, seed, model)
            print(f"  {route} seed {seed} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    t = pd.DataFrame(rows)
    if args.csv:
        t.to_csv(args.csv, index=False)
    from experiments.scripts.tyrex_pdr import md

    piv = t.pivot_table(index="variant", columns=["route", "seed"], values="end_error_pct")
    piv.columns = [f"{r} {s}" for r, s in piv.columns]
    piv["median"] = t.groupby("variant")["end_error_pct"].median()
    piv["distance ratio (median)"] = t.groupby("variant")["distance_ratio"].median()
    print("### end-point error, % of the distance, per route and seed")
    print(md(piv, "{:.2f}"))
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
