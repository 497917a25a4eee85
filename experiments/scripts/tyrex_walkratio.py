"""How true step length follows cadence on tyrex, and a literature walk-ratio default scored against today's (issue 27).

``python -m experiments.scripts.tyrex_walkratio [--data ../shared/data] [--cache FILE] [--plot FILE] [--csv FILE] [--measure-only]
[--sim DIR]``
from the repository root.

1. **Measure.** For every tyrex recording with motion capture (read as
   :func:`experiments.scripts.tyrex_pdr.load_tyrex` reads it), the default step detector's steps
   get, through :func:`gaitml.pdr.calibrate.step_length_samples` (the library code
   ``python -m gaitml.pdr.calibrate --truth self`` runs), their cadence (``freq_hz``: 1 / the
   detected step period, what the step-length model is given) and their true length (the
   low-passed body track's displacement since the step before; none after a pause or a gap).
   Per person and motion: median cadence, median true length, median walk ratio
   ``L / cadence`` in m per (steps/min), the speed ``L f``, and the least-squares slope of ``L``
   on ``f`` within the group; a scatter plot of ``L`` against ``f`` per motion with both rules
   drawn on it.
2. **Score** (skipped with ``--measure-only``). ``gaitml pdr``'s default run (forward-only,
   :func:`gaitml.pdr.run_pdr` with the default detector, heading and bias removal) is kept per
   recording; its trajectory is rebuilt with each candidate's step lengths (the heading and steps
   do not change between rows, as in :mod:`experiments.scripts.tyrex_steplen`), and scored with
   :func:`gaitml.evaluation.trajectory.walk_scores` (distance ratio, 10 s error, drift). Rows:

   - ``today``: the uncalibrated :data:`gaitml.pdr.step_length.DEFAULT_LINEAR` walk line
     ``L = 0.25 + 0.25 f`` (what ``gaitml pdr`` does today);
   - ``walk ratio``: ``L = WALK_RATIO_M_PER_SPM * 60 f`` (:data:`WALK_RATIO_M_PER_SPM`, from the gait
     literature, not fitted here). Run steps keep Weinberg (forward-only gives every step the walk
     line, as ``gaitml pdr`` does without ``--model``).

3. **Simulator** (``--sim``): rules 2 and 3 of the report for every candidate, in one run with today's
   figures: :func:`experiments.scripts.gsd_landmarks.scoring` (``gaitml pdr --truth`` on simulated walk-only
   GetSensorData routes, seeds 0-2, with ``--step-length`` a JSON of the candidate's walk line) and the ``cli
   defaults`` row of :func:`experiments.scripts.pdr_defaults_sim.cli_rows` (8 mixed-mode routes). The cadence cap
   has no model kind in the library (eq. 12 cannot hold a cadence), so for the capped candidate
   :meth:`gaitml.pdr.step_length.StepLengthModel.predict` is given the cadence clipped at the cap
   (:func:`capped_cadence`, a lab patch restored on exit; forward-only gives every step the walk line).

Nothing is fitted on tyrex, so in-sample and held-out figures are the same numbers; the
per-person table gives the spread from one person to the next. The adoption rule was fixed in
``experiments/reports/tyrex-pdr.md`` (section "A walk-ratio default?") before the score ran.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import MOTION_ORDER, _truth_on_recording, load_tyrex, md

__all__ = ["CANDIDATES", "WALK_RATIO_M_PER_SPM", "candidate_lengths", "capped_cadence", "main", "measure_table", "prepare", "sim_rules"]

#: Walk ratio (step length / cadence) of healthy adults, m per (steps/min): about 0.0064 (Sekiya &
#: Nagasaki 1998, as quoted in issue 27's brief; the constancy over preferred-to-fast speeds is
#: restated by Murakami & Otaka, J. Phys. Ther. Sci. 29:722, 2017, who find it breaks below about
#: 62 m/min and 98 steps/min, the walk ratio rising as people slow down).
WALK_RATIO_M_PER_SPM = 0.0064
#: Cadence at which adults leave walking for running, about 140 steps/min (e.g. the abstract of PMC8629136,
#: "the natural transition from walking to running occurs in adults at ~140 steps/min"): the walk ratio is a
#: walking law, so the capped candidate holds the cadence there.
WALK_RUN_TRANSITION_HZ = 140.0 / 60.0
#: the step-length rules scored: name -> (walk line (A m, B m s, C) of paper 003 eq. 12, cadence cap Hz or None)
CANDIDATES = {
    "today": ((0.25, 0.25, 0.0), None),
    "walk ratio": ((0.0, WALK_RATIO_M_PER_SPM * 60.0, 0.0), None),
    "walk ratio, capped": ((0.0, WALK_RATIO_M_PER_SPM * 60.0, 0.0), WALK_RUN_TRANSITION_HZ),
}
WALK_MOTIONS = ("Texting", "Phoning", "Swinging", "FrontPocket", "BackPocket")


def prepare(item) -> dict:
    """One recording: its steps' cadence and true length, and ``gaitml pdr``'s default forward-only run."""
    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.pdr import run_pdr
    from gaitml.pdr.calibrate import step_length_samples
    from gaitml.steps import get_detector

    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    table = get_detector(DEFAULT_STEP_DETECTOR).detect(rec).steps_
    samples = step_length_samples(rec, item["mode"], truth=(tt, item["truth"].pos_m[:, :2]), steps=table)
    res = run_pdr(rec, steps=table, modes="forward")
    st = res.steps
    return {
        "file": item["file"],
        "samples": samples[["t_s", "freq_hz", "true_length_m"]].reset_index(drop=True),
        "t_step": st[st.attrs.get("event", "t_peak_s")].to_numpy(float) if len(st) else np.zeros(0),
        "theta": st["heading_rad"].to_numpy(float) if len(st) else np.zeros(0),
        "modes": st["mode"].to_numpy().astype(str) if len(st) else np.zeros(0, dtype=str),
        "features": st[["freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2"]].reset_index(drop=True),
        "lengths_run": st["step_length_m"].to_numpy(float) if len(st) else np.zeros(0),
        "t_end": float(rec.t_s[-1]),
    }


def candidate_lengths(prep: dict, candidate) -> np.ndarray:
    """The run's steps' lengths with the candidate's walk line (library model; run keeps Weinberg), cadence capped if it says so."""
    from gaitml.pdr.step_length import StepLengthModel

    walk_line, cap = candidate
    if not len(prep["t_step"]):
        return np.zeros(0)
    feats = prep["features"].copy()
    if cap is not None:
        feats["freq_hz"] = np.minimum(feats["freq_hz"], cap)
    L = StepLengthModel({"walk": ("linear", walk_line)}).predict(feats, prep["modes"])
    return np.where(np.isfinite(L), L, 0.0)


@contextlib.contextmanager
def capped_cadence(cap_hz: float | None):
    """Within the block, :meth:`StepLengthModel.predict` sees every step's cadence clipped at ``cap_hz`` (None: unchanged)."""
    from gaitml.pdr.step_length import StepLengthModel

    if cap_hz is None:
        yield
        return
    original = StepLengthModel.predict

    def predict(self, features, modes):
        f = features.copy()
        f["freq_hz"] = np.minimum(f["freq_hz"].to_numpy(float), cap_hz)
        return original(self, f, modes)

    StepLengthModel.predict = predict
    try:
        yield
    finally:
        StepLengthModel.predict = original


def sim_rules(out: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Rules 2 and 3 for every candidate: GetSensorData landmark simulation and the simulator's routes (CLI defaults row)."""
    from experiments.scripts.gsd_landmarks import scoring
    from experiments.scripts.pdr_defaults_sim import cli_rows
    from gaitml.pdr.step_length import StepLengthModel

    gsd, sim = [], []
    for name, (line, cap) in CANDIDATES.items():
        args, model = [], None
        if name != "today":
            model = StepLengthModel({"walk": ("linear", line)})
            path = out / f"{name.replace(' ', '-').replace(',', '')}.json"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(model.to_dict()))
            args = ["--step-length", str(path)]
        with capped_cadence(cap):
            g = scoring(out / "gsd", ["rectangle", "arc"], [0, 1, 2], "start-heading", args)
            rows = [r for route in ("rectangle", "arc") for seed in (0, 1, 2, 11) for r in cli_rows(route, seed, model)]
        gsd.append(g.assign(candidate=name))
        sim.append(pd.DataFrame(rows).query("variant == 'cli defaults'").assign(candidate=name))
    return pd.concat(gsd, ignore_index=True), pd.concat(sim, ignore_index=True)


def measure_table(items, preps) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per step (cadence, true length) and per person x motion summary."""
    parts = []
    for it, p in zip(items, preps, strict=True):
        s = p["samples"]
        ok = np.isfinite(s["true_length_m"]) & np.isfinite(s["freq_hz"]) & (s["freq_hz"] > 0)
        parts.append(
            pd.DataFrame(
                {
                    "subject": it["subject"],
                    "phone": it["phone"],
                    "motion": it["motion"],
                    "disturbance": it["disturbance"],
                    "freq_hz": s["freq_hz"][ok].to_numpy(float),
                    "true_length_m": s["true_length_m"][ok].to_numpy(float),
                }
            )
        )
    steps = pd.concat(parts, ignore_index=True)
    steps["walk_ratio"] = steps["true_length_m"] / (60.0 * steps["freq_hz"])
    steps["speed_ms"] = steps["true_length_m"] * steps["freq_hz"]

    def summary(g: pd.DataFrame) -> pd.Series:
        f, L = g["freq_hz"].to_numpy(), g["true_length_m"].to_numpy()
        slope = float(np.polyfit(f, L, 1)[0]) if len(f) > 5 and np.ptp(f) > 0 else float("nan")
        fm = float(np.median(f))
        return pd.Series(
            {
                "steps": len(g),
                "cadence_hz": fm,
                "cadence_spm": 60.0 * fm,
                "true_L_m": float(np.median(L)),
                "walk_ratio": float(np.median(g["walk_ratio"])),
                "speed_ms": float(np.median(g["speed_ms"])),
                "slope_m_per_hz": slope,
                "today_L_m": float(np.polyval(CANDIDATES["today"][0][1::-1], fm)),
                "walk_ratio_L_m": float(np.polyval(CANDIDATES["walk ratio"][0][1::-1], min(fm, WALK_RUN_TRANSITION_HZ))),
            }
        )

    rows = []
    for keys, g in steps.groupby(["motion", "subject"]):
        rows.append({"motion": keys[0], "subject": keys[1], **summary(g)})
    for motion, g in steps.groupby("motion"):
        rows.append({"motion": motion, "subject": "all", **summary(g)})
    table = pd.DataFrame(rows)
    table["motion"] = pd.Categorical(table["motion"], [m for m in MOTION_ORDER if m in set(table["motion"])], ordered=True)
    return steps, table.sort_values(["motion", "subject"]).reset_index(drop=True)


def plot(steps: pd.DataFrame, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    motions = [m for m in MOTION_ORDER if m in set(steps["motion"])]
    fig, axes = plt.subplots(2, 4, figsize=(16, 8), sharex=True, sharey=True)
    f = np.linspace(0.8, 3.2, 50)
    for ax, motion in zip(axes.ravel(), motions, strict=False):
        g = steps[steps["motion"] == motion]
        for subj, gs in g.groupby("subject"):
            ax.scatter(gs["freq_hz"], gs["true_length_m"], s=2, alpha=0.25, label=subj)
        for name, ((a, b, _c), cap) in CANDIDATES.items():
            ax.plot(f, a + b * np.minimum(f, cap or np.inf), lw=1.5, ls="--" if cap else "-", label=name)
        ax.set_title(motion)
        ax.set_xlim(0.8, 3.2)
        ax.set_ylim(0.0, 1.4)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(markerscale=4, fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("detected cadence (steps/s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("true step length (m)")
    fig.suptitle("tyrex: true step length (motion capture) against cadence, per motion and person")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def score_table(items, preps) -> pd.DataFrame:
    from gaitml.evaluation.trajectory import walk_scores
    from gaitml.pdr.update import forward_update

    rows = []
    for it, p in zip(items, preps, strict=True):
        tt, txy = _truth_on_recording(it)
        for name, cand in CANDIDATES.items():
            L = candidate_lengths(p, cand)
            xy = forward_update(L, p["theta"]) if len(L) else np.zeros((1, 2))
            t = np.concatenate([[0.0], p["t_step"]])
            if t[-1] < p["t_end"]:
                t, xy = np.append(t, p["t_end"]), np.vstack([xy, xy[-1:]])
            rows.append(
                {
                    **{k: it[k] for k in ("file", "subject", "phone", "motion", "disturbance")},
                    "variant": name,
                    **walk_scores(t, xy, tt, txy),
                    "mean_length_m": float(np.mean(L)) if len(L) else 0.0,
                }
            )
    return pd.DataFrame(rows)


def _pivot(df: pd.DataFrame, metric: str, index: str = "variant") -> pd.DataFrame:
    out = df.pivot_table(index=index, columns="motion", values=metric, aggfunc="median", observed=True)
    return out[[m for m in MOTION_ORDER if m in out.columns]]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording runs: read if present, else written")
    p.add_argument("--plot", metavar="FILE", default="runs/tyrex-walkratio.png", help="the scatter plot (PNG)")
    p.add_argument("--csv", metavar="FILE", help="write the per-recording score table")
    p.add_argument("--measure-only", action="store_true", help="part 1 only (the measurement), no candidate scored")
    p.add_argument("--sim", metavar="DIR", help="also score rules 2 and 3 on the simulator (walks written to DIR)")
    a = p.parse_args(argv)
    t0 = time.time()
    items = load_tyrex(Path(a.data))
    if a.cache and Path(a.cache).is_file():
        preps = pickle.loads(Path(a.cache).read_bytes())
    else:
        preps = [prepare(it) for it in items]
        if a.cache:
            Path(a.cache).parent.mkdir(parents=True, exist_ok=True)
            Path(a.cache).write_bytes(pickle.dumps(preps))
    if [pr["file"] for pr in preps] != [it["file"] for it in items]:
        print("error: the cache does not match the data; delete it and rerun.", file=sys.stderr)
        return 2
    steps, table = measure_table(items, preps)
    print("## True step length against cadence (all recordings, default detector's steps with a true length)\n")
    print(md(table.assign(walk_ratio=table["walk_ratio"] * 1e3), "{:.3f}"))
    print("\n(walk_ratio in mm per (steps/min); walk_ratio_L_m: the capped walk-ratio rule at the median cadence)")
    walking = steps[steps["motion"].isin(WALK_MOTIONS)]
    for name, g in (("walking motions", walking), ("NoDist walking", walking[walking["disturbance"] == "NoDist"])):
        q = np.percentile(g["freq_hz"], [5, 25, 50, 75, 95])
        print(
            f"\n{name}: cadence percentiles 5/25/50/75/95 = " + " / ".join(f"{v:.2f}" for v in q) + " steps/s, "
            f"walk ratio median {np.median(g['walk_ratio']):.4f} m/(steps/min), speed median {np.median(g['speed_ms']):.2f} m/s, "
            f"share of steps below 98 steps/min {np.mean(g['freq_hz'] < 98 / 60):.2f}, below 62 m/min {np.mean(g['speed_ms'] < 62 / 60):.2f}"
        )
    if a.plot:
        plot(steps, Path(a.plot))
        print(f"\nplot: {a.plot}")
    if not a.measure_only:
        sc = score_table(items, preps)
        if a.csv:
            Path(a.csv).parent.mkdir(parents=True, exist_ok=True)
            sc.to_csv(a.csv, index=False)
        nd = sc[sc["disturbance"] == "NoDist"]
        for metric, fmt in (("distance_ratio", "{:.2f}"), ("error_10s_pct", "{:.1f}")):
            if metric not in sc:
                continue
            print(f"\n## {metric}, median, NoDist (9 per motion)\n")
            print(md(_pivot(nd, metric), fmt))
            print(f"\n## {metric}, median, all recordings\n")
            print(md(_pivot(sc, metric), fmt))
            print(f"\n## {metric}, median per person (all recordings)\n")
            per = sc.pivot_table(index=["variant", "subject"], columns="motion", values=metric, aggfunc="median", observed=True)
            print(md(per[[m for m in MOTION_ORDER if m in per.columns]].reset_index(), fmt))
        dr = _pivot(nd, "distance_ratio")
        print("\n## Rule (1): |distance ratio - 1| change against today, NoDist medians (negative = toward 1)\n")
        for name in [c for c in CANDIDATES if c != "today"]:
            moves = (dr.loc[name] - 1).abs() - (dr.loc["today"] - 1).abs()
            print(md(moves.to_frame(name).T, "{:+.3f}"))
            walk = moves[[m for m in WALK_MOTIONS if m in moves.index]]
            ok = bool((walk < 0).all() and (moves <= 0.05).all())
            print(
                f"\n{name}: rule (1) {'passes' if ok else 'fails'}: toward 1 in {int((walk < 0).sum())} of {len(walk)} walking "
                f"motions; largest move away {moves.max():+.3f} ({moves.idxmax()})\n"
            )
    if a.sim:
        gsd, sim = sim_rules(Path(a.sim))
        g = gsd[gsd["truth"].isin(["dense", "landmarks"])].groupby(["candidate", "route", "truth"], sort=False)[["mean_m", "end_%D"]].mean()
        print("\n## Rule (2): GetSensorData landmark simulation, mean over seeds 0-2\n")
        print(md(g.reset_index(), "{:.3f}"))
        today = g.loc["today"]
        for name in [c for c in CANDIDATES if c != "today"]:
            c = g.loc[name]
            ok = bool(((c["mean_m"] <= 1.05 * today["mean_m"]) & (c["end_%D"] <= today["end_%D"] + 0.1)).all())
            ratio = (c["mean_m"] / today["mean_m"]).to_numpy()
            print(
                f"\n{name}: rule (2) {'passes' if ok else 'fails'}: mean landmark error {ratio.min():.2f}-{ratio.max():.2f} x today's, "
                f"end error {(c['end_%D'] - today['end_%D']).min():+.3f} to {(c['end_%D'] - today['end_%D']).max():+.3f} points"
            )
        piv = sim.pivot_table(index="candidate", columns=["route", "seed"], values="end_error_pct", sort=False)
        piv.columns = [f"{r} {s}" for r, s in piv.columns]
        piv["median"] = sim.groupby("candidate", sort=False)["end_error_pct"].median()
        piv["distance ratio (median)"] = sim.groupby("candidate", sort=False)["distance_ratio"].median()
        print("\n## Rule (3): simulator routes, CLI defaults, end error % of the distance\n")
        print(md(piv, "{:.2f}"))
        for name in [c for c in CANDIDATES if c != "today"]:
            ok = piv.loc[name, "median"] <= 1.05 * piv.loc["today", "median"]
            print(
                f"\n{name}: rule (3) {'passes' if ok else 'fails'}: median {piv.loc[name, 'median']:.2f} % against {piv.loc['today', 'median']:.2f} %"
            )
    print(f"\n({time.time() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
