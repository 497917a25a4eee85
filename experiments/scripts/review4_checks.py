"""Review checks of HDE's structure guard and adaptive's stage 5a (branch review4; experiments/reports/review4.md).

Every figure of the report's tables, from the library as it is:

- ``false-alarm``: how often uniform headings (no dominant directions) pass :func:`gaitml.pdr.hde.direction_structure`
  at the scan's best rate, against its ``STRUCTURE_ALPHA`` (module Notes step 6: the union bound should keep it below).
- ``min-steps``: the first step whose heading the buffered feedback changes (``STRUCTURE_MIN_STEPS`` says 13 steps).
- ``roads``: ``gaitml pdr --json`` on a loop walk and a corridor walk (the synthetic walks of
  ``tests/pdr/test_hde_guard.py``) read whole and in 30 s chunks: the guard's decision, statistic, stderr warnings.
- ``routes``: the guard's record of the ``multi / true modes / hde`` variant on the simulator's routes.
- ``octave``: adaptive's stage 5a off, step peaks against the ``--base`` revision's ``adaptive_steps`` on tyrex and
  Oxford recordings (with and without the gyroscope); and ``attrs['octave']`` of a chunked run against a whole one.

    PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data python -m experiments.scripts.review4_checks --base 7ea9426
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import importlib.util
import io
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def false_alarm(seed: int = 123) -> list[dict]:
    from gaitml.pdr.hde import STRUCTURE_ALPHA, direction_structure, estimate_drift_rate

    rng = np.random.default_rng(seed)
    rows = []
    for n, draws in ((20, 3000), (150, 3000), (600, 1000)):
        t = np.arange(n) * 0.5
        hits = 0
        for _ in range(draws):
            u = rng.uniform(-np.pi, np.pi, n)
            hits += direction_structure(u, t, estimate_drift_rate(u, t), min_steps=0)["structured"]
        rows.append({"n_steps": n, "draws": draws, "passed": hits / draws, "alpha": STRUCTURE_ALPHA})
    return rows


def min_steps() -> list[dict]:
    from gaitml.pdr.hde import hde_correct

    rows = []
    for n in (12, 13, 14):
        _, corr, _ = hde_correct(np.full(n, np.deg2rad(3.0)), np.full(n, 0.5))
        first = np.flatnonzero(corr)
        rows.append({"n_steps": n, "first_corrected_step": int(first[0]) + 1 if len(first) else None})
    return rows


def _cli(*argv) -> tuple[dict, str]:
    from gaitml.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        assert main(["pdr", *map(str, argv)]) == 0
    return json.loads(out.getvalue()), err.getvalue()


def roads(tmp: str) -> list[dict]:
    import gaitml.chunked_run as cr
    import gaitml.io.chunked as ch
    from gaitml.io import write_gaitml_csv
    from tests.pdr.test_hde_guard import _corridor_recording, _loop_recording

    rows = []
    saved = (ch.LARGE_INPUT_SAMPLES, ch._ROWS_PER_READ, cr.DEFAULT_CHUNK_S, cr.DEFAULT_MARGIN_S)
    for name, rec in (("loop (400 steps)", _loop_recording(2, n=400)), ("corridor (4 x 30 steps)", _corridor_recording())):
        p = os.path.join(tmp, f"{name.split()[0]}.csv")
        write_gaitml_csv(rec, p)
        for guard in ("on", "off"):
            argv = (p, "--modes", "forward", "--gyro-bias", "off", "--hde-guard", guard, "--json")
            whole, err_w = _cli(*argv)
            ch.LARGE_INPUT_SAMPLES, ch._ROWS_PER_READ, cr.DEFAULT_CHUNK_S, cr.DEFAULT_MARGIN_S = 1000, 999, 30.0, 5.0
            try:
                long, err_l = _cli(*argv)
            finally:
                ch.LARGE_INPUT_SAMPLES, ch._ROWS_PER_READ, cr.DEFAULT_CHUNK_S, cr.DEFAULT_MARGIN_S = saved
            a = np.array([[r["x_m"], r["y_m"]] for r in whole["trajectory"]])
            b = np.array([[r["x_m"], r["y_m"]] for r in long["trajectory"]])
            cw, cl = whole["heading_check"], long["heading_check"]
            rows.append(
                {
                    "walk": name,
                    "guard": guard,
                    "applied whole / chunked": f"{cw['hde_applied']} / {cl['hde_applied']}",
                    "statistic whole": round(cw["statistic"], 6),
                    "statistic diff": abs(cw["statistic"] - cl["statistic"]),
                    "threshold": round(cw["threshold"], 4),
                    "max position diff m": float(np.abs(a - b).max()),
                    "warnings whole / chunked": f"{err_w.count('HDE not applied')} / {err_l.count('HDE not applied')}",
                    "same json keys": set(whole) == set(long) and set(cw) == set(cl),
                }
            )
    return rows


def routes() -> list[dict]:
    from gaitml.pipeline.pdr_routes import VARIANTS, evaluate_route

    v = [("multi / true modes / hde", dict(VARIANTS)["multi / true modes / hde"])]
    rows = []
    for route in ("rectangle", "arc", "straight", "random"):
        for seed in (1, 2):
            (r,) = evaluate_route(route, seed, variants=v, keep_results=True)
            c = r["result"].info["heading_check"]
            rows.append(
                {
                    "route": route,
                    "seed": seed,
                    "steps": c["n_steps"],
                    "statistic": round(c["statistic"], 3),
                    "threshold": round(c["threshold"], 3),
                    "hde_applied": r["hde_applied"],
                }
            )
    return rows


def octave(base: str, tmp: str) -> list[dict]:
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.recording import Recording
    from gaitml.steps import adaptive as new
    from gaitml.steps import get_detector
    from tests.steps.test_adaptive_octave import ON, _slow_short_walk

    src = subprocess.run(["git", "show", f"{base}:gaitml/steps/adaptive.py"], capture_output=True, text=True, check=True).stdout
    path = os.path.join(tmp, "base_adaptive.py")
    with open(path, "w") as f:
        f.write(src)
    spec = importlib.util.spec_from_file_location("base_adaptive", path)
    old = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(old)
    data = os.environ.get("GAITML_SHARED_DATA", "/work/shared/data")
    files = (
        sorted(glob.glob(f"{data}/tyrex-attitude/android/*Texting*"))[:3]
        + sorted(glob.glob(f"{data}/tyrex-attitude/android/*Swinging*"))[:2]
    )
    files += sorted(glob.glob(f"{data}/oxford-step-counter/optimisation/data/*"))[:2]
    rows = []
    for f in files:
        rec = read_recording(f)
        for gyr in ([rec.gyr] if rec.has_gyr else []) + [None]:
            a = old.adaptive_steps(new.acc_magnitude(rec), rec.sampling_rate_hz, gyr_rads=gyr)
            b = new.adaptive_steps(new.acc_magnitude(rec), rec.sampling_rate_hz, gyr_rads=gyr)
            same = all(np.array_equal(a[k], b[k]) for k in ("peak", "period_s", "correlation", "confidence"))
            rows.append(
                {
                    "check": f"off vs {base}",
                    "input": os.path.basename(f),
                    "gyro": gyr is not None,
                    "steps": len(b["peak"]),
                    "identical": same,
                }
            )
    x, _ = _slow_short_walk(0, 20)
    y, _ = _slow_short_walk(2, 20)
    p = os.path.join(tmp, "two_slow_walks.csv")
    write_gaitml_csv(Recording.from_arrays(np.vstack([x.acc, y.acc]), 100.0, gyr=np.vstack([x.gyr, y.gyr])), p)
    whole = get_detector("adaptive", **ON).detect(read_recording(p)).steps_.attrs["octave"]
    for chunk_s, margin_s in ((40.0, 10.0), (20.0, 10.0)):
        got = long_steps(p, "adaptive", chunk_s=chunk_s, margin_s=margin_s, progress=False, detector_params=ON).attrs["octave"]
        rows.append(
            {"check": f"attrs['octave'] chunked {chunk_s:g} s / {margin_s:g} s", "input": "two slow walks", "whole": whole, "chunked": got}
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.review4_checks", description=__doc__.split("\n")[0])
    p.add_argument("--base", default="7ea9426", help="revision whose adaptive_steps the default (stage 5a off) must equal")
    p.add_argument("--only", nargs="+", choices=("false-alarm", "min-steps", "roads", "routes", "octave"))
    args = p.parse_args(argv)
    import pandas as pd

    wanted = args.only or ("false-alarm", "min-steps", "roads", "routes", "octave")
    with tempfile.TemporaryDirectory() as tmp:
        for name in wanted:
            rows = {
                "false-alarm": false_alarm,
                "min-steps": min_steps,
                "roads": lambda: roads(tmp),
                "routes": routes,
                "octave": lambda: octave(args.base, tmp),
            }[name]()
            print(f"\n## {name}")
            with pd.option_context("display.width", 250, "display.max_columns", 20, "display.max_colwidth", 60):
                print(pd.DataFrame(rows).to_string(index=False))
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
