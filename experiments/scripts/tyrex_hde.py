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
  candidate guard's statistic and threshold (:func:`direction_structure`);
- forward-only trajectories (default step length) with the heading variants in
  :func:`heading_variants` (plain gyro, HDE as shipped, its two parts alone, HDE behind the
  candidate structure guard :func:`guarded_hde`), each scored with
  :func:`gaitml.evaluation.trajectory.walk_scores` (walking-direction drift, 10 s error,
  distance ratio) against the capture.

With ``--sim-seeds`` it also prints the guard's statistic against its threshold on the
simulator's rectangle and arc routes (``gaitml pdr``'s steps and gyro headings, start heading
from the reference), the corridor-like routes on which HDE must keep correcting.

Tables: medians per motion (NoDist, 9 per motion, as ``tyrex-pdr.md`` section 3, and all), the
number of motions where each variant drifts no more than the plain gyroscope, and per person.

The candidate guard (not adopted: its adoption rule failed in AR, ``experiments/reports/tyrex-pdr.md``,
"HDE in a room"). HDE's premise is that the walker mainly walks along the dominant directions; a
walk looping round a 5 m room turns all the time and its step headings cover the circle, so the
whole-recording rate fit lines them up by chance. The guard corrects only when the alignment score
at the fitted rate, ``S = mean cos(n (theta - rate t - reference))``, exceeds what headings without
dominant-direction structure reach by chance: for N independent headings uniform on the circle
``P(|mean exp(i n theta)| > s) ~ exp(-N s^2)`` (the Rayleigh test of ``n theta``; Mardia and Jupp,
*Directional Statistics*, 2000, sec. 6.3.1), ``S`` is at most that resultant length at every rate,
and the fit scans about ``K = 1 + n (2 max_rate) T / (2 pi)`` independent rates (the phase ``n r t``
turns by 2 pi over the duration T when the rate moves by ``2 pi / (n T)``), so by the union bound
``P(max S > s) <= K exp(-N s^2)``; the threshold is ``sqrt(ln(K / alpha) / N)`` with
``alpha`` = :data:`STRUCTURE_ALPHA`. Otherwise the gyro heading is kept (no rate, no feedback).
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

__all__ = ["direction_structure", "guarded_hde", "heading_variants", "main", "sim_structure", "step_data"]

#: uniform-heading draws per recording for the chance level of the fitted score
N_NULL = 20
#: the candidate guard's false-alarm probability: the chance that step headings without
#: dominant-direction structure pass it (a conventional level, set before measuring, not fitted)
STRUCTURE_ALPHA = 0.01
#: the half-width of the rate range :func:`gaitml.pdr.hde.estimate_drift_rate` scans (its default, rad/s)
MAX_DRIFT_RATE_RADS = 0.03


def direction_structure(
    heading_rad, t_s, rate_rads: float = 0.0, *, n_directions: int = 12, reference_rad: float = 0.0, alpha: float = STRUCTURE_ALPHA
) -> dict:
    """Whether step headings line up with the dominant directions more than chance allows (module docstring).

    Returns ``statistic`` (``mean cos(n (heading - rate (t - t_0) - reference))``), ``threshold``
    (``sqrt(ln(K / alpha) / N)``), ``structured`` (statistic > threshold), ``n_steps`` (N) and
    ``n_rates`` (K, the independent rates of the fit's scan).
    """
    psi = np.unwrap(np.asarray(heading_rad, dtype=float).reshape(-1))
    t = np.asarray(t_s, dtype=float).reshape(-1)
    n = len(psi)
    if n == 0:
        return {"statistic": 0.0, "threshold": float("inf"), "structured": False, "n_steps": 0, "n_rates": 1.0}
    k = 1.0 + n_directions * 2.0 * MAX_DRIFT_RATE_RADS * float(t[-1] - t[0]) / (2 * np.pi)
    stat = float(np.mean(np.cos(n_directions * (psi - rate_rads * (t - t[0]) - reference_rad))))
    thr = float(np.sqrt(np.log(k / alpha) / n))
    return {"statistic": stat, "threshold": thr, "structured": bool(stat > thr), "n_steps": n, "n_rates": k}


def guarded_hde(heading_rad, step_duration_s, step_t_s, *, reference_rad: float = 0.0) -> tuple[np.ndarray, dict]:
    """HDE as shipped (:func:`gaitml.pdr.hde.hde_heading`) when :func:`direction_structure` finds structure
    at the fitted rate, else the gyro headings unchanged; and the guard's record."""
    from gaitml.pdr.hde import estimate_drift_rate, hde_heading

    psi = np.asarray(heading_rad, dtype=float).reshape(-1)
    if len(psi) < 2:
        return psi, direction_structure(psi, step_t_s, reference_rad=reference_rad)
    rate = estimate_drift_rate(psi, step_t_s, reference_rad=reference_rad)
    st = direction_structure(psi, step_t_s, rate, reference_rad=reference_rad)
    if not st["structured"]:
        return psi, st
    return hde_heading(psi, step_duration_s, step_t_s, reference_rad=reference_rad)[0], st


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
    out["hde"] = hde_heading(psi, dur, t)[0]
    out["hde rate only"] = hde_heading(psi, dur, t, feedback=0.0)[0]
    out["hde feedback only"] = hde_heading(psi, dur, t, drift_rate="none")[0]
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
    dg["structured"] = dg["structure"] > dg["structure_threshold"]
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
