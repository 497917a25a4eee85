"""Which bouts of ``adaptive``'s steps pass the gait check, and the bout features a new gait-evidence test can use.

Runs ``adaptive`` with the gait check off (swing stage off and on: ``gyro_swing_min_periodicity`` 0 / 0.3) on

- the simulated non-gait recordings (``gaitml.simulate.nongait``; ``--seeds selection`` = 0-39, ``heldout`` = 100-119),
- the tyrex walking and running recordings (steps inside the motion-capture span only),
- simulated slow walkers (``experiments.scripts.slow_walks``) and bag walks (``experiments.scripts.bag_gait_check``),

and writes one row per bout of steps (:func:`gaitml.steps._gait_evidence.step_bouts`) with the features of
:func:`bout_features` (rotation, vertical / horizontal acceleration and |acc| amplitudes at half, one and two times
the step frequency) to a pickle (cached per set under ``--cache``).

``--select`` then chooses the two rotation-free rules of the gait check (the check is a bout filter after
detection, so the choice runs on the cached bouts; ``--sets tyrex-ar`` must be cached too):

1. the vertical test: a bout of fewer than ``LONG_BOUT_STEPS`` steps whose share of the vertical acceleration's
   variance at the stride frequency exceeds F (inf: off). For each tyrex person left out, a setting is admissible
   when it costs the other two people at most 0.1 % of their steps in the motion-capture span (the five walking
   motions) and none of their AR steps (the slowest real walks); among those, the one leaving the fewest steps per
   minute on the simulated gestures + desk selection seeds 0-39 (swing stage off) is chosen (ties: the one costing
   the two people fewer steps), and the left-out person's loss is printed;
2. the short-bout context rule (opt-in): a bout of fewer than 10 steps that holds, with the bouts reaching within
   G s of it, fewer than M steps, with F fixed; the same choice without the AR condition (no setting that removes
   desk steps keeps every AR step). G is at most 30 s (the chunk margin of ``gaitml.chunked_run``).

Only selection seeds are read.

    python -m experiments.scripts.gait_check_study --data ../shared/data --cache /tmp/gaitcheck   # ~5 min
    python -m experiments.scripts.gait_check_study --data ../shared/data --cache /tmp/gaitcheck --sets tyrex-ar
    python -m experiments.scripts.gait_check_study --cache /tmp/gaitcheck --select
"""

from __future__ import annotations

import argparse
import pickle
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import FIT_RATE_HZ, GAP_RATIO, rotation_amplitude, step_bouts


def _block_mean(x: np.ndarray, q: int) -> np.ndarray:
    m = len(x) // q
    return x[: m * q].reshape(m, q, -1).mean(axis=1)


def bout_features(gyr, acc, sampling_rate_hz: float, steps: pd.DataFrame, *, gap_ratio: float = GAP_RATIO) -> pd.DataFrame:
    """Per bout: rotation (``r_*``), vertical (``v_*``), horizontal (``h_*``) and |acc| (``m_*``) amplitudes at f/2, f, 2f and their SDs."""
    fs = float(sampling_rate_hz)
    ev = steps.attrs.get("event", "t_peak_s")
    if len(steps) == 0:
        return pd.DataFrame()
    t = steps[ev].to_numpy(dtype=float)
    period = steps["period_s"].to_numpy(dtype=float) if "period_s" in steps.columns else None
    bout = step_bouts(t, period, gap_ratio=gap_ratio)
    a_all = np.asarray(acc, dtype=float)
    g_all = None if gyr is None else np.asarray(gyr, dtype=float)
    q = max(1, int(fs // FIT_RATE_HZ))
    from scipy.ndimage import uniform_filter1d

    rows = []
    for b in range(int(bout[-1]) + 1):
        idx = np.flatnonzero(bout == b)
        tb = t[idx]
        row = {"bout": b, "first": int(idx[0]), "last": int(idx[-1]), "n_steps": len(idx), "t_start_s": tb[0], "t_end_s": tb[-1]}
        if len(idx) >= 2:
            d = np.diff(tb)
            f = 1.0 / float(np.median(d))
            row["cv"] = float(np.std(d) / np.mean(d))
        else:
            f = np.nan
        row["step_hz"] = f
        if len(idx) >= 2:
            half = 0.5 / f
            a = max(0, int(np.floor((tb[0] - half) * fs)))
            e = min(len(a_all), int(np.ceil((tb[-1] + half) * fs)) + 1)
            w = max(1, int(round(2.0 * fs / f)))
            a0, e0 = max(0, a - w), min(len(a_all), e + w)
            grav = uniform_filter1d(a_all[a0:e0], w, axis=0, mode="nearest")[a - a0 : a - a0 + (e - a)]
            acc_b = a_all[a:e]
            u = grav / np.maximum(np.linalg.norm(grav, axis=1, keepdims=True), 1e-9)
            vert = np.sum(acc_b * u, axis=1, keepdims=True)
            hor = acc_b - vert * u
            V = _block_mean(vert, q)
            H = _block_mean(hor, q)
            M = _block_mean(np.linalg.norm(acc_b, axis=1, keepdims=True), q)
            if len(V) >= 8:
                fr = (f / 2.0, f, 2.0 * f)
                for name, X in (("v", V), ("h", H), ("m", M)):
                    amp = rotation_amplitude(X, fs / q, *fr)
                    row[f"{name}_half"], row[f"{name}_f"], row[f"{name}_2f"] = (float(x) for x in amp)
                    row[f"{name}_std"] = float(np.sqrt(np.sum(np.var(X, axis=0))))
                if g_all is not None:
                    G = _block_mean(g_all[a:e], q)
                    amp = rotation_amplitude(G, fs / q, *fr)
                    row["r_half"], row["r_f"], row["r_2f"] = (float(x) for x in amp)
                    row["r_std"] = float(np.sqrt(np.sum(np.var(G, axis=0))))
        rows.append(row)
    return pd.DataFrame(rows)


SWING = {"off": 0.0, "on": 0.3}


def _bouts(rec, steps, keep=None) -> pd.DataFrame:
    ev = bout_features(rec.gyr, rec.acc, rec.sampling_rate_hz, steps)
    if keep is not None and len(ev):
        ev["n_in_span"] = [int(keep[r.first : r.last + 1].sum()) for r in ev.itertuples()]
    else:
        ev["n_in_span"] = ev["n_steps"] if len(ev) else []
    return ev


def _run(rec, meta: dict, keep_fn=None) -> list[pd.DataFrame]:
    out = []
    for sw, v in SWING.items():
        st = get_detector("adaptive", gait_check=False, gyro_swing_min_periodicity=v).detect(rec).steps_
        keep = keep_fn(st) if keep_fn else None
        ev = _bouts(rec, st, keep)
        for k, val in {**meta, "swing": sw, "n_total": int(len(st) if keep is None else keep.sum())}.items():
            ev[k] = val
        out.append(ev)
    return out


def nongait_bouts(seeds) -> pd.DataFrame:
    from gaitml.simulate.nongait import simulate_nongait

    rows = []
    for kind in ("gestures", "desk"):
        for s in seeds:
            rec = simulate_nongait(kind, duration_s=120, seed=s)
            rows += _run(rec, {"set": kind, "rec": f"{kind}{s}", "seed": s, "minutes": rec.duration_s / 60, "n_true": 0})
            print(f"{kind} {s}", file=sys.stderr)
    return pd.concat(rows, ignore_index=True)


def tyrex_bouts(data, motions=None) -> pd.DataFrame:
    from experiments.scripts.tyrex_steps import tyrex_walks
    from experiments.scripts.tyrex_steps_lopo import SCORED

    rows = []
    for it in tyrex_walks(data, motions or SCORED):
        for j, r in enumerate(it["recs"]):
            t0 = float(r.meta.get("t0_original_s", 0.0))

            def keep_fn(st, t0=t0, it=it):
                tt = t0 + st["t_peak_s"].to_numpy()
                return (tt >= it["ref"]["t_first_s"]) & (tt <= it["ref"]["t_last_s"])

            meta = {
                "set": "tyrex",
                "rec": it["name"],
                "seg": j,
                "motion": it["motion"],
                "person": it["person"],
                "n_true": it["ref"]["n_steps"],
            }
            rows += _run(r, meta, keep_fn)
        print(it["name"], file=sys.stderr)
    return pd.concat(rows, ignore_index=True)


def slow_bouts(seeds) -> pd.DataFrame:
    from experiments.scripts.slow_walks import POSITIONS, slow_recording

    rows = []
    for pos in POSITIONS:
        for s in seeds:
            rec = slow_recording(s, pos)
            n_true = int(rec.reference["n_steps_true"]) if "n_steps_true" in rec.reference else int(len(rec.reference["steps"]))
            rows += _run(rec, {"set": f"slow-{pos}", "rec": f"{pos}{s}", "seed": s, "n_true": n_true})
        print(f"slow {pos}", file=sys.stderr)
    return pd.concat(rows, ignore_index=True)


def bag_bouts(seeds) -> pd.DataFrame:
    from experiments.scripts.bag_gait_check import walk_recording

    rows = []
    for pos in ("bag", "swinging-hand", "back-pocket"):
        for s in seeds:
            rec = walk_recording(pos, s)
            n_true = int(rec.reference["n_steps_true"])
            rows += _run(rec, {"set": f"walk-{pos}", "rec": f"{pos}{s}", "seed": s, "n_true": n_true})
        print(f"walk {pos}", file=sys.stderr)
    return pd.concat(rows, ignore_index=True)


def cached(cache: Path, name: str, fn, *args) -> pd.DataFrame:
    p = cache / f"{name}.pkl"
    if p.exists():
        return pickle.loads(p.read_bytes())
    df = fn(*args)
    p.write_bytes(pickle.dumps(df))
    return df


PEOPLE_STEPS_MOTIONS = ("Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging")
PEOPLE = ("Guillaume", "Jakob", "Thibaud")
GRID_F_ALONE = (0.3, 0.35, 0.38, 0.4, 0.42, 0.45, 0.5, np.inf)
#: the shipped MAX_STRIDE_VERTICAL_FRACTION (chosen by the first LOPO)
SHIPPED_F = 0.4
GRID_G = (8.0, 10.0, 15.0, 20.0, 30.0)
GRID_M = (10, 15, 20, 30)
MARGIN = 0.001
#: 40 selection recordings of 120 s per non-gait kind
SELECTION_MINUTES = 40 * 2.0


#: --all-bouts-context: every bout counts as context (the short-bout rule as first shipped)
ALL_BOUTS_CONTEXT = False


def _rotation_rejects(d: pd.DataFrame) -> pd.Series:
    """The shipped rotation test (0.7 rad/s, above the stride's, below 30 steps) on the cached bouts."""
    return (d.r_f > 0.7) & (d.r_f > d.r_half) & (d.n_steps < 30)


def bout_context(d: pd.DataFrame, key: list[str], g: float, standing: pd.Series | None = None) -> np.ndarray:
    """Steps of the other bouts reaching within ``g`` s of each bout (whole bouts counted, as the library does).

    ``standing``: only these bouts count (the library counts the bouts that stand on their own: at least
    ``confirm_bout_steps`` steps, passing the rotation and vertical tests); None: every bout (the rule as first
    shipped, when short runs confirmed one another)."""
    c = np.zeros(len(d))
    d = d.reset_index(drop=True)
    ok = np.ones(len(d), dtype=bool) if standing is None else np.asarray(standing, dtype=bool)
    for _, grp in d.groupby(key):
        ts, te, n = grp.t_start_s.to_numpy(), grp.t_end_s.to_numpy(), grp.n_steps.to_numpy()
        s = ok[grp.index.to_numpy()]
        for k, i in enumerate(grp.index):
            o = (te > ts[k] - g) & (ts < te[k] + g) & s
            o[k] = False
            c[i] = n[o].sum()
    return c


def _load_selection(cache: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    ng = pickle.loads((cache / "nongait_selection.pkl").read_bytes()).reset_index(drop=True)
    ty = pickle.loads((cache / "tyrex.pkl").read_bytes())
    ty = ty[ty.motion.isin(PEOPLE_STEPS_MOTIONS)]
    ty = pd.concat([ty, pickle.loads((cache / "tyrex_ar.pkl").read_bytes())]).reset_index(drop=True)
    for d in (ng, ty):
        d["rot"] = _rotation_rejects(d)
        d["vfrac"] = (d.v_half**2 / 2) / d.v_std**2
    return ng, ty


def grid_rejects(d: pd.DataFrame, f: float, m: int) -> pd.Series:
    """Bouts the rotation test, the vertical test (share > ``f``) or the context rule (``m`` steps; 0: off) reject."""
    r = d.rot | ((d.vfrac > f) & (d.n_steps < 30))
    return r | ((d.n_steps < 10) & (d.n_steps + d.ctx < m)) if m else r


def standing_bouts(d: pd.DataFrame, f: float) -> pd.Series | None:
    """The bouts that count as a short bout's context: >= 10 steps, passing the rotation and vertical tests
    (None with ``--all-bouts-context``: every bout, the rule as first shipped)."""
    if ALL_BOUTS_CONTEXT:
        return None
    return ~grid_rejects(d, f, 0) & (d.n_steps >= 10)


def _grid_rows(ng: pd.DataFrame, ty: pd.DataFrame, settings) -> pd.DataFrame:
    """Steps per minute (non-gait) and tyrex steps lost per person (walking motions; AR apart) per (F, G, M) setting."""
    rows = []
    for g, m, f in settings:
        if m:
            ng["ctx"] = bout_context(ng, ["rec", "swing"], g, standing_bouts(ng, f))
            ty["ctx"] = bout_context(ty, ["rec", "seg", "swing"], g, standing_bouts(ty, f))
        for sw in ("off", "on"):
            n, t = ng[ng.swing == sw], ty[ty.swing == sw]

            rn, rt = grid_rejects(n, f, m), grid_rejects(t, f, m)
            row = {"F": f, "G": g, "M": m, "swing": sw}
            for kind in ("gestures", "desk"):
                row[kind] = n[~rn & (n.set == kind)].n_steps.sum() / SELECTION_MINUTES
            for p in PEOPLE:
                lost = t[rt & ~t.rot & (t.person == p)]
                row[p] = int(lost[lost.motion != "AR"].n_in_span.sum())
                row[f"{p} AR"] = int(lost[lost.motion == "AR"].n_in_span.sum())
            rows.append(row)
    return pd.DataFrame(rows)


def _lopo(grid: pd.DataFrame, tot: pd.Series, ar_zero: bool) -> list[str]:
    out = []
    r = grid[grid.swing == "off"]
    for p in PEOPLE:
        tr = [q for q in PEOPLE if q != p]
        lost = r[tr].sum(axis=1) / tot[tr].sum()
        ok = lost <= MARGIN
        if ar_zero:
            ok &= r[[f"{q} AR" for q in tr]].sum(axis=1) == 0
        c = r[ok].assign(s=lambda d: d.gestures + d.desk, lost=lost[ok]).sort_values(["s", "lost"])
        none = c.empty
        if none:  # nothing admissible: the setting that costs the other two people least
            c = r.assign(s=lambda d: d.gestures + d.desk, lost=lost).sort_values(["lost", "s"])
        b = c.iloc[0]
        setting = ("none admissible; least loss: " if none else "") + f"{b.F:g}" + (f", {b.G:g} s, {int(b.M)}" if b.M else "")
        out.append(
            f"| {p} | {setting} | {int(r.loc[b.name, tr].sum())} ({lost[b.name]:.4f}) | "
            f"{int(b[p])} of {int(tot[p])} ({b[p] / tot[p]:.4f}) | {int(b[f'{p} AR'])} | {b.gestures:.3f} / {b.desk:.3f} |"
        )
    return out


def select(cache: Path) -> str:
    """The leave-one-person-out choices (module docstring) and the grid, as markdown."""
    ng, ty = _load_selection(cache)
    tot = ty[(ty.swing == "off") & (ty.motion != "AR")].groupby("person").n_in_span.sum()
    head = [
        "| left out | chosen | other two: walking steps lost (share) | left out: walking steps lost (of) | left out: AR steps lost | "
        "gestures / desk steps/min (seeds 0-39) |",
        "|---|---|---|---|---|---|",
    ]
    vert = _grid_rows(ng, ty, [(0.0, 0, f) for f in GRID_F_ALONE])
    ctx = _grid_rows(ng, ty, [(g, m, SHIPPED_F) for g in GRID_G for m in GRID_M])
    out = ["Vertical test alone (F), admissible: <= 0.1 % walking steps and 0 AR steps lost on the other two people:", ""]
    out += head + _lopo(vert, tot, ar_zero=True)
    out += ["", f"Opt-in short-bout rule (G, M) with F = {SHIPPED_F:g}, admissible: <= 0.1 % walking steps (AR not constrained):", ""]
    out += head + _lopo(ctx, tot, ar_zero=False)
    cols = ["F", "G", "M", "swing", "gestures", "desk", *PEOPLE, *[f"{p} AR" for p in PEOPLE]]
    for name, g in (("vertical test alone", vert), ("short-bout rule", ctx)):
        out += ["", f"Grid, {name} (steps lost per person in the walking motions and in AR):", ""]
        out += ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        for row in g[cols].itertuples(index=False):
            out.append("| " + " | ".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in row) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.gait_check_study", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default="/tmp/gaitcheck")
    ap.add_argument("--seeds", choices=("selection", "heldout"), default="selection")
    ap.add_argument("--sets", default="nongait,tyrex,slow,walk")
    ap.add_argument("--select", action="store_true", help="print the leave-one-person-out choice from the cached bouts")
    ap.add_argument("--all-bouts-context", action="store_true", help="--select with every bout as context (the rule as first shipped)")
    a = ap.parse_args(argv)
    global ALL_BOUTS_CONTEXT
    ALL_BOUTS_CONTEXT = a.all_bouts_context
    cache = Path(a.cache)
    cache.mkdir(parents=True, exist_ok=True)
    if a.select:
        print(select(cache))
        return 0
    sel = a.seeds == "selection"
    for s in a.sets.split(","):
        if s == "nongait":
            cached(cache, f"nongait_{a.seeds}", nongait_bouts, range(40) if sel else range(100, 120))
        elif s == "tyrex":
            cached(cache, "tyrex", tyrex_bouts, a.data)
        elif s == "tyrex-ar":
            cached(cache, "tyrex_ar", tyrex_bouts, a.data, ("AR",))
        elif s == "slow":
            cached(cache, f"slow_{a.seeds}", slow_bouts, range(8) if sel else range(100, 120))
        elif s == "walk":
            cached(cache, f"walk_{a.seeds}", bag_bouts, range(40) if sel else range(100, 130))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
