"""Adaptive's per-bout octave decision (stage 5a) on the tyrex recordings, leave-one-person-out (issue 30).

Stage 5a (:func:`gaitml.steps.adaptive.bout_octave`): each walking bout's octave is decided once, from the phone's
swing pooled over the whole bout (one cycle per stride), and a bout read at two peaks per step (or one per stride)
has its steps picked again at the swing's step; a short bout whose octave the swing decided passes the short-bout
rule when its step intervals are regular. Two settings: ``octave_swing_min_correlation`` (0 = off) and
``max_short_bout_interval_cv`` (0 = no exemption).

The adoption rule was fixed before the first measurement (experiments/reports/tyrex-steps.md, the octave section):
for each person left out, the setting of :data:`GRID` (or off) with the best score on the other two people (mean
over the seven scored motions of the mean count accuracy against the motion-capture count,
:mod:`experiments.scripts.tyrex_steps_lopo`) is scored on the person left out, and stage 5a becomes the default only
if (A1) no left-out person's score falls, (A2) Texting and Phoning pooled over the held-out people rise, (A3) no motion
of any held-out person falls by more than 0.01, (A4) the simulated non-gait held-out seeds 100-119 give no more steps
per minute, (A5) the simulated slow walkers (held-out seeds) do not fall, (A6) the Oxford and IFSM step times (no
gyroscope) are identical. This script prints A1-A3 (default mode), A4-A5 (``--sim``) and A6 (``--no-gyroscope``).

    python -m experiments.scripts.tyrex_steps_octave [--data ../shared/data]              # LOPO, A1-A3, ~30 s
    python -m experiments.scripts.tyrex_steps_octave --matching --setting 0.5,0.2         # per-step hits / extras / misses
    python -m experiments.scripts.tyrex_steps_octave --bouts --setting 0.5,0.2           # half-step bouts against the reference
    python -m experiments.scripts.tyrex_steps_octave --sim --setting 0.5,0.2 [--cache D]   # non-gait and slow walkers
    python -m experiments.scripts.tyrex_steps_octave --no-gyroscope --setting 0.5,0.2     # Oxford and IFSM
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED, _counts, _load, _score
from experiments.scripts.tyrex_steps_swing import per_person_markdown

#: stage 5a's two settings: octave_swing_min_correlation, max_short_bout_interval_cv (fixed before measuring)
GRID = {"octave_swing_min_correlation": (0.3, 0.5, 0.7), "max_short_bout_interval_cv": (0.0, 0.1, 0.2)}
OFF = (0.0, 0.0)
#: A3: the most a motion of a held-out person may fall
MAX_MOTION_LOSS = 0.01


def _settings() -> list[tuple]:
    return [OFF, *itertools.product(*GRID.values())]


def _params(k: tuple, **extra) -> dict:
    return {**dict(zip(GRID, k, strict=True)), **extra}


def _name(k: tuple) -> str:
    return "off" if k == OFF else ", ".join(f"{v:g}" for v in k)


def _per_motion(df: pd.DataFrame) -> pd.Series:
    return df.groupby("motion")["acc"].mean()


def lopo(grid: dict[tuple, pd.DataFrame]) -> tuple[str, dict[str, bool], pd.DataFrame]:
    """Per person left out: the setting chosen on the other two, its training and held-out score, per motion, and A1-A3."""
    off = grid[OFF]
    cols = ["left out", "chosen", "training score", "held-out score", "held-out, off", *SCORED]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    held_rows, a1, a3 = [], True, True
    for held in PEOPLE:
        train = {k: _score(v[v["person"] != held]) for k, v in grid.items()}
        best = max(train, key=train.get)
        te, te0 = grid[best][grid[best]["person"] == held], off[off["person"] == held]
        held_rows.append(te)
        per, per0 = _per_motion(te), _per_motion(te0)
        a1 &= _score(te) >= _score(te0) - 1e-12
        a3 &= bool(((per - per0) >= -MAX_MOTION_LOSS).all())
        cells = [held, _name(best), f"{train[best]:.4f}", f"{_score(te):.4f}", f"{_score(te0):.4f}"]
        cells += [f"{per[m]:.3f} ({per0[m]:.3f})" for m in SCORED]
        out.append("| " + " | ".join(cells) + " |")
    pooled = pd.concat(held_rows)
    pm, pm0 = _per_motion(pooled), _per_motion(off)
    a2 = bool(pm["Texting"] > pm0["Texting"] and pm["Phoning"] > pm0["Phoning"])
    out.append(
        "| pooled held out | | | "
        + f"{_score(pooled):.4f} | {_score(off):.4f} | "
        + " | ".join(f"{pm[m]:.3f} ({pm0[m]:.3f})" for m in SCORED)
        + " |"
    )
    return "\n".join(out), {"A1": a1, "A2": a2, "A3": a3}, pooled


def fold_choices(grid: dict[tuple, pd.DataFrame]) -> list[tuple]:
    """The setting each leave-one-person-out fold chooses on its two training people."""
    out = []
    for held in PEOPLE:
        train = {k: _score(v[v["person"] != held]) for k, v in grid.items()}
        out.append(max(train, key=train.get))
    return out


def insample(grid: dict[tuple, pd.DataFrame]) -> str:
    """Every setting on all three people, best first, per motion."""
    allp = {k: _score(v) for k, v in grid.items()}
    out = ["| setting | score | " + " | ".join(SCORED) + " |", "|" + "---|" * (2 + len(SCORED))]
    for k in sorted(allp, key=allp.get, reverse=True):
        per = _per_motion(grid[k])
        out.append(f"| {_name(k)} | {allp[k]:.4f} | " + " | ".join(f"{per[m]:.3f}" for m in SCORED) + " |")
    return "\n".join(out)


def match_steps(t: np.ndarray, ref: np.ndarray, tol: float = 0.45) -> tuple[int, int, int]:
    """Greedy one-to-one matching of detected to reference step times within ``tol`` s: hits, extras, misses."""
    used = np.zeros(len(ref), dtype=bool)
    hit = 0
    for x in np.sort(t):
        j = np.flatnonzero(~used & (np.abs(ref - x) <= tol))
        if len(j):
            used[j[np.argmin(np.abs(ref[j] - x))]] = True
            hit += 1
    return hit, len(t) - hit, len(ref) - hit


def matching(items: list[dict], runs: dict[str, dict]) -> str:
    """Per motion and person: reference steps matched by a detected step within 0.45 s (hits), detected steps matched
    by none (extras), reference steps unmatched (misses), for each run's settings (recordings whose reference counts
    steps, not strides)."""
    from gaitml.steps import get_detector

    rows = []
    for it in items:
        if it["ref"]["steps_per_event"] != 1:
            continue
        ref = np.asarray(it["ref"]["t_s"])
        for name, params in runs.items():
            tt = []
            for r in it["recs"]:
                st = get_detector("adaptive", **params).detect(r).steps_
                t = float(r.meta.get("t0_original_s", 0.0)) + st["t_peak_s"].to_numpy()
                tt.append(t[(t >= it["ref"]["t_first_s"]) & (t <= it["ref"]["t_last_s"])])
            h, e, m = match_steps(np.concatenate(tt), ref)
            rows.append({"motion": it["motion"], "person": it["person"], "run": name, "hits": h, "extras": e, "misses": m})
    df = pd.DataFrame(rows).groupby(["motion", "person", "run"], sort=False)[["hits", "extras", "misses"]].sum()
    df["F1"] = 2 * df["hits"] / (2 * df["hits"] + df["extras"] + df["misses"])
    out = ["| motion | person | run | hits | extras | misses | F1 |", "|---|---|---|---|---|---|---|"]
    for (mo, pe, ru), r in df.iterrows():
        out.append(f"| {mo} | {pe} | {ru} | {r['hits']} | {r['extras']} | {r['misses']} | {r['F1']:.3f} |")
    return "\n".join(out)


def half_step_bouts(items: list[dict], params: dict) -> str:
    """Every bout stage 5a reads as half-steps on the Texting and Phoning recordings: its peaks, the reference's steps
    inside it (+-0.3 s), its median peak interval, the swing's step (half its pooled stride period) and the median
    interval of the reference's steps inside it (s); then how often the swing's step is within 10 % / 20 % of the
    reference's."""
    from gaitml.steps import adaptive as A

    seen: list[tuple] = []
    base = A.bout_octave

    def recording(pk, bout, *args, **kw):
        octave, step = base(pk, bout, *args, **kw)
        seen.append((pk.copy(), bout.copy(), octave.copy(), step.copy(), float(args[2])))
        return octave, step

    rows = []
    A.bout_octave = recording
    try:
        for it in items:
            if it["motion"] not in ("Texting", "Phoning"):
                continue
            ref = np.asarray(it["ref"]["t_s"])
            for r in it["recs"]:
                seen.clear()
                A.AdaptiveStepDetector(**params).detect(r)
                t0 = float(r.meta.get("t0_original_s", 0.0))
                for pk, bout, octave, step, fs in seen:
                    for b in np.flatnonzero(octave == 2):
                        p = pk[bout == b] / fs + t0
                        inside = ref[(ref >= p[0] - 0.3) & (ref <= p[-1] + 0.3)]
                        rows.append(
                            {
                                "recording": it["name"],
                                "person": it["person"],
                                "peaks": len(p),
                                "reference steps": len(inside),
                                "peak interval": float(np.median(np.diff(p))),
                                "swing step": step[b] / fs,
                                "reference interval": float(np.median(np.diff(inside))) if len(inside) > 1 else np.nan,
                            }
                        )
    finally:
        A.bout_octave = base
    df = pd.DataFrame(rows)
    if df.empty:
        return "no bout read as half-steps"
    v = df[df["reference steps"] >= 2]
    ratio = (v["swing step"] / v["reference interval"] - 1).abs()
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in df.iterrows():
        out.append("| " + " | ".join(f"{r[c]:.2f}" if isinstance(r[c], float) else str(r[c]) for c in cols) + " |")
    out.append("")
    out.append(
        f"{len(df)} bouts read as half-steps ({int((df['person'] == 'Guillaume').sum())} Guillaume's); of the {len(v)} with two "
        f"reference steps or more, the swing's step is within 10 % of the reference's interval in {int((ratio <= 0.1).sum())} "
        f"and within 20 % in {int((ratio <= 0.2).sum())}"
    )
    return "\n".join(out)


def simulated(params: dict, cache: str | None) -> str:
    """A4 and A5: adaptive off and with ``params`` on the held-out simulated non-gait seeds and slow walkers."""
    import pickle

    from experiments.scripts.slow_walks import HELDOUT_SEEDS, POSITIONS, SELECTION_SEEDS, count_accuracy, slow_recording
    from gaitml.simulate.nongait import simulate_nongait
    from gaitml.steps import get_detector

    runs = {"off": {}, "on": params}
    out = ["| set | off: mean (worst) | on: mean (worst) |", "|---|---|---|"]
    seeds = tuple(range(100, 120))
    path = Path(cache) / "nongait_recs_100_119.pkl" if cache else None
    if path is not None and path.exists():
        recs = pickle.loads(path.read_bytes())
    else:
        recs = {(kind, s): simulate_nongait(kind, duration_s=120, seed=s) for kind in ("gestures", "desk") for s in seeds}
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(pickle.dumps(recs))
    for kind in ("gestures", "desk"):
        cells = []
        for p in runs.values():
            per = [len(get_detector("adaptive", **p).detect(recs[(kind, s)]).steps_) / (recs[(kind, s)].duration_s / 60) for s in seeds]
            cells.append(f"{np.mean(per):.3f} ({np.max(per):.1f})")
        out.append(f"| non-gait {kind}, seeds 100-119, steps/min | " + " | ".join(cells) + " |")
    for label, sd in (("selection 0-7", SELECTION_SEEDS), ("held-out 100-119", HELDOUT_SEEDS)):
        for position in POSITIONS:
            acc = {k: [] for k in runs}
            for s in sd:
                rec = slow_recording(s, position)
                for k, p in runs.items():
                    acc[k].append(count_accuracy(rec.reference["n_steps_true"], len(get_detector("adaptive", **p).detect(rec).steps_)))
            cells = [f"{np.mean(acc[k]):.3f} ({np.min(acc[k]):.3f})" for k in runs]
            out.append(f"| slow walkers {position}, {label}, count accuracy | " + " | ".join(cells) + " |")
    return "\n".join(out)


def no_gyroscope(data: str | Path, params: dict) -> str:
    """A6: adaptive off and with ``params`` on the Oxford and IFSM recordings (no gyroscope): identical step times?"""
    from gaitml.io.ifsm import read_ifsm_xlsx
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder
    from gaitml.steps import get_detector

    root = Path(data)
    recs = []
    for f in list_oxford_folders(root / "oxford-step-counter"):
        r = read_oxford_folder(f)
        recs.extend(r if isinstance(r, list) else [r])
    recs += [read_ifsm_xlsx(f) for f in sorted((root / "ifsm-flat-phone").rglob("*.xlsx"))]
    same = n0 = n1 = 0
    for r in recs:
        a = get_detector("adaptive").detect(r).steps_["t_peak_s"].to_numpy()
        b = get_detector("adaptive", **params).detect(r).steps_["t_peak_s"].to_numpy()
        same += int(np.array_equal(a, b))
        n0, n1 = n0 + len(a), n1 + len(b)
    n_gyr = sum(r.has_gyr for r in recs)
    return f"{len(recs)} Oxford and IFSM recordings, {n_gyr} with a gyroscope; identical step times {same}/{len(recs)}; steps {n0} (off) vs {n1} (on)"


def adfsm_counts(items: list[dict]) -> pd.DataFrame:
    """AD-FSM's count accuracy per recording (the floor adaptive must not fall below)."""
    from gaitml.steps import get_detector

    rows = []
    for it in items:
        n = 0
        for r in it["recs"]:
            st = get_detector("adfsm").detect(r).steps_
            tt = float(r.meta.get("t0_original_s", 0.0)) + st["t_peak_s"].to_numpy()
            n += int(np.sum((tt >= it["ref"]["t_first_s"]) & (tt <= it["ref"]["t_last_s"])))
        n_ref = it["ref"]["n_steps"]
        rows.append({"motion": it["motion"], "person": it["person"], "acc": 1 - abs(n - n_ref) / max(n_ref, 1)})
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> int:
    """Print the leave-one-person-out choice and the adoption checks (or one of the other modes)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_octave", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--setting", default=None, help="octave_swing_min_correlation,max_short_bout_interval_cv for the other modes")
    ap.add_argument("--matching", action="store_true", help="per-step hits / extras / misses on the trunk motions, off and --setting")
    ap.add_argument("--sim", action="store_true", help="simulated non-gait (held-out seeds) and slow walkers, off and --setting")
    ap.add_argument("--no-gyroscope", action="store_true", help="Oxford and IFSM (no gyroscope), off and --setting")
    ap.add_argument(
        "--bouts", action="store_true", help="the Texting and Phoning bouts read as half-steps at --setting, against the reference"
    )
    ap.add_argument("--cache", default=None, help="folder for the simulated non-gait recordings")
    a = ap.parse_args(argv)
    if (a.matching or a.sim or a.no_gyroscope or a.bouts) and not a.setting:
        print("error: --matching, --bouts, --sim and --no-gyroscope need --setting RHO,CV (e.g. 0.5,0.2)", file=sys.stderr)
        return 2
    params = None
    if a.setting:
        try:
            k = tuple(float(v) for v in a.setting.split(","))
            params = _params(k)
        except ValueError:
            print(f"error: --setting must be two numbers RHO,CV (e.g. 0.5,0.2), got {a.setting!r}", file=sys.stderr)
            return 2
    if a.sim:
        print(simulated(params, a.cache))
        return 0
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    if a.no_gyroscope:
        print(no_gyroscope(a.data, params))
        return 0
    items = _load(a.data)
    if a.bouts:
        print(half_step_bouts(items, params))
        return 0
    if a.matching:
        trunk = [it for it in items if it["motion"] in ("Texting", "Phoning", "FrontPocket", "BackPocket")]
        on = {f"on ({a.setting})": params, f"on ({a.setting}) + stage 2c": {**params, "gyro_swing_min_periodicity": 0.3}}
        print(matching(trunk, {"off": {}, **on, "stage 2c alone": {"gyro_swing_min_periodicity": 0.3}}))
        return 0
    grid = {}
    for k in _settings():
        grid[k] = _counts(items, **_params(k))
        print(f"tyrex {_name(k)}: {_score(grid[k]):.4f}", file=sys.stderr)
    table, checks, _ = lopo(grid)
    print("Leave-one-person-out: the setting chosen on the other two people, scored on the person left out")
    print("(setting = " + ", ".join(GRID) + "; cells: held out with the chosen setting (off))\n")
    print(table)
    print("\nAdoption checks on tyrex: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
    allp = {k: _score(v) for k, v in grid.items()}
    best = max(allp, key=allp.get)
    print(f"\nIn sample (all three people): best {_name(best)} ({allp[best]:.4f}; off {allp[OFF]:.4f})\n")
    print(insample(grid))
    runs = {"off (today)": grid[OFF], f"in-sample choice {_name(best)}": grid[best]}
    # the settings some fold chose (and the in-sample choice), alone and with the opt-in stage 2c
    chosen = [k for k in dict.fromkeys([*fold_choices(grid), best]) if k != OFF]
    for k in chosen:
        runs[f"{_name(k)}"] = grid[k]
        runs[f"{_name(k)} + stage 2c (0.3)"] = _counts(items, **_params(k, gyro_swing_min_periodicity=0.3))
    runs["stage 2c (0.3) alone"] = _counts(items, gyro_swing_min_periodicity=0.3)
    runs["adfsm"] = adfsm_counts(items)
    print("\nPer person (in sample):\n")
    print(per_person_markdown(runs))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
