"""Why HDE drifts more than the plain gyroscope heading on the tyrex room loops (issue 27), per recording.

``python -m experiments.scripts.tyrex_hde [--data ../shared/data] [--cache FILE] [--csv FILE] [--out FILE]``
from the repository root (about 3 minutes; ``--cache`` keeps the per-recording steps, gyro step
headings and truth so a rerun only rescores, seconds).

Per tyrex recording with motion capture (read as in :mod:`experiments.scripts.tyrex_pdr`), the
steps and gyro step headings of ``gaitml pdr`` at its defaults (``run_pdr(heading='gyro')``:
the same steps, attitude and gyroscope-bias removal HDE starts from), then:

- the drift-rate fit of :func:`gaitml.pdr.hde.estimate_drift_rate`: the fitted rate, the
  alignment score ``mean cos(n (psi - r t))`` at the fitted rate and at zero, and what the
  same fit gives on headings uniform on the circle at the same step times (median of
  :data:`N_NULL` draws; the chance level of a score maximised over the rate grid), and the
  guard's statistic and threshold (:func:`gaitml.pdr.hde.direction_structure`);
- forward-only trajectories (default step length) with the heading variants in
  :func:`heading_variants` (plain gyro, HDE with its structure guard off, its two parts alone, HDE
  with the guard: the library's default, :func:`guarded_hde`), each scored with
  :func:`gaitml.evaluation.trajectory.walk_scores` (walking-direction drift, 10 s error,
  distance ratio) against the capture.

With ``--sim-seeds`` it also prints the guard's statistic against its threshold on the
simulator's rectangle and arc routes (``gaitml pdr``'s steps and gyro headings, start heading
from the reference), the corridor-like routes on which HDE must keep correcting.

Tables: medians per motion (NoDist, 9 per motion, as ``tyrex-pdr.md`` section 3, and all), the
number of motions where each variant drifts no more than the plain gyroscope, and per person.

The guard (adopted by the lead, post hoc, ``experiments/reports/tyrex-pdr.md``, "HDE in a room") is the
library's: :func:`gaitml.pdr.hde.direction_structure` and ``hde_heading(structure_alpha=...)`` (module Notes
step 6 of :mod:`gaitml.pdr.hde`): HDE corrects only when the alignment score at the scan's best rate beats
what headings without dominant-direction structure reach by chance, on at least
:data:`gaitml.pdr.hde.STRUCTURE_MIN_STEPS` steps; otherwise the gyro heading is kept. Here ``hde`` is HDE with
the guard off (as shipped before it) and ``hde guarded`` the library's default.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import MOTION_ORDER, load_tyrex, md
from gaitml.pdr.hde import direction_structure

__all__ = ["guarded_hde", "heading_variants", "main", "sim_structure", "step_data"]

#: uniform-heading draws per recording for the chance level of the fitted score
N_NULL = 20


def guarded_hde(heading_rad, step_duration_s, step_t_s, *, reference_rad: float = 0.0) -> tuple[np.ndarray, dict]:
    """The library's default HDE (structure guard on, :func:`gaitml.pdr.hde.hde_heading`): the headings and the guard's record."""
    from gaitml.pdr.hde import hde_heading

    h, _, _, _, check = hde_heading(heading_rad, step_duration_s, step_t_s, reference_rad=reference_rad)
    return h, check


def step_data(item) -> dict:
    """Steps, gyro step headings, durations and default lengths of ``gaitml pdr``'s defaults, with the truth."""
    from gaitml.pdr import run_pdr

    rec, truth = item["recording"], item["truth"]
    res = run_pdr(rec, modes="forward", heading="gyro")
    st = res.steps
    event = st.attrs.get("event", "t_peak_s")
    n = len(st)
    sr = rec.sampling_rate_hz
    return {
        **{k: item[k] for k in ("file", "subject", "phone", "motion", "disturbance")},
        "t_step": st[event].to_numpy(float) if n else np.zeros(0),
        "dur": (np.maximum(st["end"].to_numpy() - st["start"].to_numpy(), 1) / sr) if n else np.zeros(0),
        "gyro_h": st["heading_rad"].to_numpy(float) if n else np.zeros(0),
        "length": st["step_length_m"].to_numpy(float) if n else np.zeros(0),
        "t_end": float(rec.t_s[-1]),
        "tt": truth.t_s - rec.meta["t0_original_s"],
        "xy": truth.pos_m[:, :2].copy(),
    }


def heading_variants(d: dict) -> dict[str, np.ndarray]:
    """Heading per step of every variant compared."""
    from gaitml.pdr.hde import hde_heading

    psi, dur, t = d["gyro_h"], d["dur"], d["t_step"]
    out = {"gyro": psi}
    if len(psi) < 2:
        return {k: psi for k in ("gyro", "hde", "hde rate only", "hde feedback only", "hde guarded")}
    out["hde"] = hde_heading(psi, dur, t, structure_alpha=None)[0]
    out["hde rate only"] = hde_heading(psi, dur, t, feedback=0.0, structure_alpha=None)[0]
    out["hde feedback only"] = hde_heading(psi, dur, t, drift_rate="none", structure_alpha=None)[0]
    out["hde guarded"] = guarded_hde(psi, dur, t)[0]
    return out


def diagnose(d: dict, rng) -> dict:
    """The drift-rate fit of one recording: rate, scores at the fit / at zero / chance, structure."""
    from gaitml.pdr.hde import N_DIRECTIONS, estimate_drift_rate

    psi, t = np.unwrap(d["gyro_h"]), d["t_step"]
    if len(psi) < 2:
        return {}
    tr = t - t[0]
    rate = estimate_drift_rate(psi, t)

    def score(p, r):
        return float(np.mean(np.cos(N_DIRECTIONS * (p - r * tr))))

    null = []
    for _ in range(N_NULL):
        u = rng.uniform(-np.pi, np.pi, len(psi))
        null.append(score(u, estimate_drift_rate(u, t)))
    st = direction_structure(psi, t, rate)
    return {
        "n_steps": len(psi),
        "fit_rate_deg_min": np.rad2deg(rate) * 60,
        "score_fit": score(psi, rate),
        "score_zero": score(psi, 0.0),
        "score_chance": float(np.median(null)),
        "structure": st["statistic"],
        "structure_threshold": st["threshold"],
        "structured": st["structured"],
    }


def sim_structure(routes=("rectangle", "arc"), seeds=(0, 1, 2, 11)) -> pd.DataFrame:
    """The guard on the simulator's routes: statistic, threshold and fitted rate per route and seed."""
    from gaitml.pdr import run_pdr
    from gaitml.pdr.hde import estimate_drift_rate
    from gaitml.simulate import simulate_route

    rows = []
    for route in routes:
        for seed in seeds:
            rec = simulate_route(route, seed=seed)
            h0 = float(rec.reference["trajectory"]["heading_rad"].iloc[0])
            st = run_pdr(rec, modes="forward", heading="gyro", initial_heading_rad=h0).steps
            t = st[st.attrs.get("event", "t_peak_s")].to_numpy(float)
            psi = st["heading_rad"].to_numpy(float)
            rate = estimate_drift_rate(psi, t, reference_rad=h0)
            g = direction_structure(psi, t, rate, reference_rad=h0)
            rows.append({"route": route, "seed": seed, "fit_rate_deg_min": np.rad2deg(rate) * 60, **g})
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> int:
    from gaitml.evaluation.trajectory import walk_scores
    from gaitml.pdr.update import forward_update

    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_hde", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording step data: read if present, else written")
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per recording and variant)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    p.add_argument(
        "--sim-seeds", type=int, nargs="*", metavar="SEED", help="also print the guard on the simulator's routes for these seeds"
    )
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    if args.cache and Path(args.cache).exists():
        with open(args.cache, "rb") as fh:
            data = pickle.load(fh)
    else:
        items = load_tyrex(Path(args.data))
        data = []
        for i, it in enumerate(items):
            data.append(step_data(it))
            if (i + 1) % 20 == 0:
                print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        if args.cache:
            with open(args.cache, "wb") as fh:
                pickle.dump(data, fh)
    rng = np.random.default_rng(0)
    rows, diag = [], []
    for d in data:
        keys = {k: d[k] for k in ("file", "subject", "phone", "motion", "disturbance")}
        diag.append({**keys, **diagnose(d, rng)})
        for name, h in heading_variants(d).items():
            xy = forward_update(d["length"], h)
            t = np.concatenate([[0.0], d["t_step"], [d["t_end"]]])
            sc = walk_scores(t, np.vstack([xy, xy[-1:]]), d["tt"], d["xy"])
            rows.append({**keys, "variant": name, **sc})
    table = pd.DataFrame(rows)
    dg = pd.DataFrame(diag)
    gyro_drift = table[table["variant"] == "gyro"].set_index("file")["drift_deg_per_min"]
    dg["gyro_drift_deg_min"] = dg["file"].map(gyro_drift)
    if args.csv:
        table.to_csv(args.csv, index=False)
        dg.to_csv(Path(args.csv).with_suffix(".diag.csv"), index=False)
    table["abs_drift"] = table["drift_deg_per_min"].abs()
    variants = list(dict.fromkeys(table["variant"]))
    lines = []
    nd = table["disturbance"] == "NoDist"
    for subset, sel in (("NoDist (9 per motion)", nd), ("all", table.index >= 0)):
        for col, name in (("abs_drift", "|drift| deg/min"), ("error_10s_pct", "10 s error %"), ("distance_ratio", "distance ratio")):
            piv = table[sel].pivot_table(index="variant", columns="motion", values=col, aggfunc="median")
            piv = piv.reindex(index=variants, columns=[m for m in MOTION_ORDER if m in piv.columns])
            if col == "abs_drift":
                piv["motions <= gyro"] = (piv.le(piv.loc["gyro"], axis=1)).sum(axis=1)
            lines += [f"### {name}, median, {subset}", md(piv, "{:.1f}" if col != "distance_ratio" else "{:.2f}"), ""]
    dg["abs_fit"] = dg["fit_rate_deg_min"].abs()
    dg["abs_gyro_drift"] = dg["gyro_drift_deg_min"].abs()
    dg["structured"] = dg["structured"].fillna(False).astype(bool)
    cols = ["abs_fit", "abs_gyro_drift", "score_fit", "score_zero", "score_chance", "structure_threshold", "structured"]
    agg = dg.groupby("motion")[cols].agg(lambda s: s.mean() if s.dtype == bool else s.median())
    agg = agg.reindex([m for m in MOTION_ORDER if m in agg.index])
    lines += ["### drift-rate fit per motion (median; `structured`: share of recordings above the threshold)", md(agg, "{:.3f}"), ""]
    per = table[nd].pivot_table(index=["subject", "variant"], columns="motion", values="abs_drift", aggfunc="median")
    per = per.reindex(columns=[m for m in MOTION_ORDER if m in per.columns])
    lines += ["### |drift| deg/min per person, NoDist", md(per, "{:.1f}"), ""]
    if args.sim_seeds:
        sim = sim_structure(seeds=tuple(args.sim_seeds)).set_index(["route", "seed"])
        lines += ["### the guard on the simulator's routes", md(sim, "{:.3f}"), ""]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
