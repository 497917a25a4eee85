"""Is a step of ``adaptive`` with a low ``confidence`` a sign of no gait? The "unsure" threshold, chosen and scored.

``adaptive`` gives every step a ``confidence`` in [0, 1] (periodicity x timing regularity, halved for a stride
inferred from the cadence range alone, scaled down in bouts of fewer than ten steps). This script collects the
confidence of every step ``adaptive`` (defaults, gait check on) finds in:

- **real walking and running**: tyrex (``../shared/data/tyrex-attitude``, every motion, steps over the
  motion-capture span; *matched* = within 0.45 s of a motion-capture step, 0.9 s for the stride-clock motions, as
  ``experiments.scripts.tyrex_steps_misses``), the Oxford step-counter walks (48, no gyroscope), the two flat-held
  walks of the IFSM paper (``ifsm-flat-phone``);
- **simulated slow walkers** (``experiments.scripts.slow_walks``: 0.8-1.2 steps/s, hand flat / tilted / front
  pocket, 60 s), selection seeds 0-39, held-out seeds 100-129;
- **no gait** (``gaitml.simulate.nongait``: gestures, desk; 120 s), selection seeds 0-39, held-out seeds 100-129.

Two rules are scored.

1. **A threshold on the per-step confidence** (not shipped). The rule that chooses it (fixed before any figure was
   looked at): on the selection data, the largest threshold on a 0.01 grid that calls at most ``MAX_UNSURE`` (2 %)
   of the steps unsure in **every** walking group (each tyrex motion except AR, which has no reliable reference, and
   each slow-walker position). Selection data: tyrex two people (the third is scored, each in turn) and simulator
   seeds 0-39; scored on the left-out person, seeds 100-129, Oxford and the IFSM walks (never used to choose). It
   chooses 0.08-0.09, where non-gait keeps 1.1-1.9 confident steps per minute; the trade-off table shows no
   threshold meets both sides.
2. **The bout rule** of ``gaitml.steps.confident_steps`` (shipped): a step is confident when a bout of at least ten
   regular steps lies within a window of it. The window is chosen by :func:`choose_window` (the shortest on
   ``WINDOWS`` with at most 2 % unsure steps in every walking group and person of the selection data),
   leave-one-person-out on tyrex; scored also on simulator seeds 100-129, fresh seeds 300-359 (run only after the
   rule was written down), 10-minute non-gait recordings (seeds 400-419), Oxford and the IFSM walks.

Per recording it also checks the stderr note of ``gaitml steps``: a recording whose steps are MOSTLY (> half)
unsure. Real walking recordings should not raise it; non-gait ones should.

    python -m experiments.scripts.step_confidence [--data ../shared/data] [--cache /tmp/unsure] [--threshold X]

Under a minute the first time (cached per source under ``--cache`` afterwards; delete the cache after changing
``adaptive``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import CONFIDENT_WINDOW_S, get_detector
from gaitml.steps.adaptive import BOUT_GAP_RATIO, SHORT_BOUT_STEPS

SELECTION_SEEDS = tuple(range(40))
HELDOUT_SEEDS = tuple(range(100, 130))
#: seeds never run before the recording-level rule was written down (its fresh held-out score)
FRESH_SEEDS = tuple(range(300, 360))
PEOPLE = ("Guillaume", "Jakob", "Thibaud")
#: the largest share of a walking group's steps the threshold may call unsure on the selection data
MAX_UNSURE = 0.02
GRID = np.round(np.arange(0.01, 1.0, 0.01), 2)
#: tyrex motions with an unreliable reference (mostly standing): reported, not used to choose
NO_REFERENCE = ("AR",)
COVER_S = 0.45
STRIDE_MOTIONS = ("FrontPocket", "BackPocket", "Swinging", "RunningPocket", "RunningHand")


def _steps(rec) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """adaptive's step times, confidences and the size of each step's bout (``BOUT_GAP_RATIO`` as adaptive)."""
    st = get_detector("adaptive").detect(rec).steps_
    t = st["t_peak_s"].to_numpy(dtype=float)
    return t, st["confidence"].to_numpy(dtype=float), bout_sizes(t, st["period_s"].to_numpy(dtype=float))


def bout_sizes(t: np.ndarray, period_s: np.ndarray) -> np.ndarray:
    """Steps in each step's bout: an interval over ``BOUT_GAP_RATIO`` local step periods ends a bout (as adaptive)."""
    if len(t) == 0:
        return np.zeros(0, dtype=np.int64)
    gap = np.diff(t) > BOUT_GAP_RATIO * np.maximum(period_s[:-1], period_s[1:])
    bout = np.concatenate([[0], np.cumsum(gap)])
    return np.bincount(bout)[bout]


def _near(a: np.ndarray, b: np.ndarray, w: float) -> np.ndarray:
    """For each time in ``a``: is a time of ``b`` within ``w``?"""
    if len(b) == 0:
        return np.zeros(len(a), dtype=bool)
    b = np.sort(b)
    j = np.searchsorted(b, a).clip(1, max(len(b) - 1, 1)) if len(b) > 1 else np.zeros(len(a), dtype=int)
    return np.minimum(np.abs(b[j] - a), np.abs(b[np.maximum(j - 1, 0)] - a)) <= w


def tyrex_steps(data: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """adaptive's steps on every tyrex recording over the motion-capture span: (steps, recordings)."""
    from experiments.scripts.tyrex_steps import in_reference_span, tyrex_walks

    steps, recs_out = [], []
    for walk in tyrex_walks(data):
        ref, name, motion = walk["ref"], walk["name"], walk["motion"]
        tt, cc, bb = [], [], []
        for r in walk["recs"]:
            t, c, b = _steps(r)
            tt.append(float(r.meta.get("t0_original_s", 0.0)) + t)
            cc.append(c)
            bb.append(b)
        t = np.concatenate(tt) if tt else np.zeros(0)
        c = np.concatenate(cc) if cc else np.zeros(0)
        b = np.concatenate(bb) if bb else np.zeros(0, dtype=np.int64)
        ok = in_reference_span(t, ref)
        t, c, b = t[ok], c[ok], b[ok]
        w = COVER_S * (2 if motion in STRIDE_MOTIONS else 1)
        matched = _near(t, np.asarray(ref["t_s"], dtype=float), w)
        minutes = (ref["t_last_s"] - ref["t_first_s"]) / 60.0
        steps.append(pd.DataFrame({"recording": name, "t": t, "confidence": c, "bout": b, "matched": matched}))
        recs_out.append({"recording": name, "source": "tyrex", "group": motion, "person": walk["person"], "minutes": minutes})
        print(f"tyrex {name}: {len(t)} steps", file=sys.stderr, flush=True)
    return pd.concat(steps, ignore_index=True), pd.DataFrame(recs_out)


def oxford_steps(data: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """adaptive's steps on the Oxford walks (matched: within 0.45 s of the reference step counter's step)."""
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder

    steps, recs_out = [], []
    for folder in list_oxford_folders(data / "oxford-step-counter"):
        rec = read_oxford_folder(folder)
        t, c, b = _steps(rec)
        ref = np.asarray(rec.reference.get("steps_t_s", []), dtype=float)
        steps.append(pd.DataFrame({"recording": folder.name, "t": t, "confidence": c, "bout": b, "matched": _near(t, ref, COVER_S)}))
        recs_out.append(
            {
                "recording": folder.name,
                "source": "oxford",
                "group": str(rec.meta.get("position", "?")),
                "person": str(rec.meta.get("user", "?")),
                "minutes": rec.duration_s / 60.0,
            }
        )
    return pd.concat(steps, ignore_index=True), pd.DataFrame(recs_out)


def ifsm_steps(data: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """adaptive's steps on the two flat-held walks (no step times: matched is unknown, set True)."""
    from gaitml.io.ifsm import read_ifsm_xlsx

    steps, recs_out = [], []
    for k in (1, 2):
        path = data / "ifsm-flat-phone" / f"acceleration_flat_holding_{k}.xlsx"
        rec = read_ifsm_xlsx(path)
        t, c, b = _steps(rec)
        steps.append(pd.DataFrame({"recording": path.name, "t": t, "confidence": c, "bout": b, "matched": True}))
        recs_out.append(
            {"recording": path.name, "source": "ifsm-flat", "group": "flat-held", "person": f"walker{k}", "minutes": rec.duration_s / 60.0}
        )
    return pd.concat(steps, ignore_index=True), pd.DataFrame(recs_out)


def simulated_steps(seeds=SELECTION_SEEDS + HELDOUT_SEEDS) -> tuple[pd.DataFrame, pd.DataFrame]:
    """adaptive's steps on the slow walkers and the non-gait recordings, selection and held-out seeds."""
    from experiments.scripts.slow_walks import POSITIONS, slow_recording

    steps, recs_out = [], []
    for seed in seeds:
        split = "selection" if seed in SELECTION_SEEDS else "held-out" if seed in HELDOUT_SEEDS else "fresh"
        items = [(p, "slow-walk", lambda p=p, seed=seed: slow_recording(seed, p)) for p in POSITIONS]
        items += [(k, "nongait", lambda k=k, seed=seed: simulate_nongait(k, duration_s=120, seed=seed)) for k in ("gestures", "desk")]
        for group, source, make in items:
            rec = make()
            t, c, b = _steps(rec)
            matched = np.zeros(len(t), dtype=bool)
            if source == "slow-walk":
                ref = rec.reference.get("steps_t_s")
                matched = _near(t, np.asarray(ref, dtype=float), COVER_S) if ref is not None else np.ones(len(t), dtype=bool)
            name = f"{group}-{seed}"
            steps.append(pd.DataFrame({"recording": name, "t": t, "confidence": c, "bout": b, "matched": matched}))
            recs_out.append(
                {"recording": name, "source": source, "group": group, "person": split, "seed": seed, "minutes": rec.duration_s / 60.0}
            )
        print(f"simulated seed {seed}", file=sys.stderr, flush=True)
    return pd.concat(steps, ignore_index=True), pd.DataFrame(recs_out)


def collect(data: Path, cache: Path | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Every source's steps (recording, confidence, matched) and recordings, cached per source."""
    parts = {
        "tyrex": lambda: tyrex_steps(data),
        "oxford": lambda: oxford_steps(data),
        "ifsm": lambda: ifsm_steps(data),
        "sim": simulated_steps,
        "sim_fresh": lambda: simulated_steps(FRESH_SEEDS),
    }
    steps, recs = [], []
    for name, fn in parts.items():
        if cache is not None and (cache / f"{name}_steps.pkl").exists():
            s, r = pd.read_pickle(cache / f"{name}_steps.pkl"), pd.read_pickle(cache / f"{name}_recs.pkl")
        else:
            s, r = fn()
            if cache is not None:
                cache.mkdir(parents=True, exist_ok=True)
                s.to_pickle(cache / f"{name}_steps.pkl")
                r.to_pickle(cache / f"{name}_recs.pkl")
        steps.append(s)
        recs.append(r)
    recs = pd.concat(recs, ignore_index=True)
    steps = pd.concat(steps, ignore_index=True).merge(recs, on="recording", how="left")
    return steps, recs


def walking_groups(steps: pd.DataFrame) -> dict[str, np.ndarray]:
    """Confidences per walking group that the rule constrains (tyrex motions but AR, slow-walker positions)."""
    out = {}
    for (source, group), g in steps.groupby(["source", "group"]):
        if source == "tyrex" and group not in NO_REFERENCE:
            out[f"tyrex {group}"] = g["confidence"].to_numpy()
        elif source == "slow-walk":
            out[f"slow {group}"] = g["confidence"].to_numpy()
    return out


def choose_threshold(groups: dict[str, np.ndarray], max_unsure: float = MAX_UNSURE) -> float:
    """The largest grid threshold calling at most ``max_unsure`` of the steps unsure in every group."""
    best = 0.0
    for t in GRID:
        if all(np.mean(c < t) <= max_unsure for c in groups.values() if len(c)):
            best = float(t)
    return best


def unsure_table(steps: pd.DataFrame, threshold: float, by: list[str]) -> pd.DataFrame:
    """Per group: steps, the share unsure (all steps, and the steps matched to a reference step)."""
    rows = []
    for key, g in steps.groupby(by):
        key = key if isinstance(key, tuple) else (key,)
        c, m = g["confidence"].to_numpy(), g["matched"].to_numpy(dtype=bool)
        rows.append(
            dict(zip(by, key, strict=True))
            | {
                "steps": len(c),
                "unsure %": 100.0 * float(np.mean(c < threshold)) if len(c) else np.nan,
                "matched unsure %": 100.0 * float(np.mean(c[m] < threshold)) if m.any() else np.nan,
                "median conf": float(np.median(c)) if len(c) else np.nan,
                "p02 conf": float(np.quantile(c, 0.02)) if len(c) else np.nan,
            }
        )
    return pd.DataFrame(rows)


def per_recording(steps: pd.DataFrame, recs: pd.DataFrame, threshold: float) -> pd.DataFrame:
    """Per recording: steps, confident steps, confident steps per minute, and whether MOST steps are unsure."""
    g = steps.groupby("recording")["confidence"]
    n = g.size().rename("n")
    conf = g.apply(lambda c: int(np.sum(c >= threshold))).rename("n_confident")
    out = recs.set_index("recording").join(n).join(conf).fillna({"n": 0, "n_confident": 0})
    out["confident_per_min"] = out["n_confident"] / out["minutes"]
    out["steps_per_min"] = out["n"] / out["minutes"]
    out["mostly_unsure"] = (out["n"] > 0) & (out["n"] - out["n_confident"] > out["n"] / 2)
    return out.reset_index()


def nongait_summary(rec_rows: pd.DataFrame, split: str) -> pd.DataFrame:
    """Steps per minute and confident steps per minute on the non-gait recordings of one split."""
    g = rec_rows[(rec_rows.source == "nongait") & (rec_rows.person == split)]
    rows = []
    for kind, gg in g.groupby("group"):
        rows.append(
            {
                "kind": kind,
                "recordings": len(gg),
                "steps/min mean": gg.steps_per_min.mean(),
                "confident/min mean": gg.confident_per_min.mean(),
                "confident/min max": gg.confident_per_min.max(),
                "with steps": int((gg.n > 0).sum()),
                "mostly unsure (of those)": int(gg.mostly_unsure.sum()),
            }
        )
    return pd.DataFrame(rows)


def tradeoff(steps: pd.DataFrame, recs: pd.DataFrame, rules: list[tuple[float, int]]) -> pd.DataFrame:
    """For each rule (confidence threshold, shortest confident bout): unsure share of real steps against confident
    non-gait steps per minute. Real: per tyrex motion (all three people; AR apart), Oxford, slow walkers per split."""
    rows = []
    walk = steps[steps.source != "nongait"]
    ng = steps[steps.source == "nongait"]
    for t, nb in rules:
        row = {"threshold": t, "min bout": nb}
        un = (walk.confidence < t) | (walk.bout < nb)
        for motion in ("Texting", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket", "AR"):
            m = (walk.source == "tyrex") & (walk.group == motion)
            row[f"tyrex {motion} %"] = 100.0 * float(un[m].mean())
        row["oxford %"] = 100.0 * float(un[walk.source == "oxford"].mean())
        for split in ("selection", "held-out"):
            m = (walk.source == "slow-walk") & (walk.person == split)
            row[f"slow {split} worst position %"] = max(100.0 * float(un[m & (walk.group == p)].mean()) for p in walk[m].group.unique())
        for split in ("selection", "held-out"):
            for kind in ("gestures", "desk"):
                m = (ng.person == split) & (ng.group == kind)
                sure = int(((ng.confidence >= t) & (ng.bout >= nb))[m].sum())
                minutes = recs[(recs.source == "nongait") & (recs.person == split) & (recs.group == kind)].minutes.sum()
                row[f"{kind} {split} /min"] = sure / minutes
        rows.append(row)
    return pd.DataFrame(rows)


#: longer non-gait recordings (10 min): the chance of one long bout grows with the length
LONG_SEEDS = tuple(range(400, 420))
#: windows tried for the bout rule (s; inf: the whole recording)
WINDOWS = (0.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, np.inf)


def confident_within(t: np.ndarray, bout: np.ndarray, window_s: float, min_bout: int = SHORT_BOUT_STEPS) -> np.ndarray:
    """Per step of one recording: a step of a bout of ``min_bout`` steps lies within ``window_s`` of it (the rule of
    ``gaitml.steps.confident_steps``, on the cached step times and bout sizes)."""
    t = np.asarray(t, dtype=float)
    tc = np.sort(t[np.asarray(bout) >= min_bout])
    if len(tc) == 0:
        return np.zeros(len(t), dtype=bool)
    j = np.searchsorted(tc, t)
    d = np.minimum(np.abs(t - tc[np.clip(j - 1, 0, len(tc) - 1)]), np.abs(tc[np.clip(j, 0, len(tc) - 1)] - t))
    return d <= window_s


def with_window(steps: pd.DataFrame, window_s: float) -> pd.DataFrame:
    """``steps`` with a column ``ok``: confident under the bout rule with ``window_s``."""
    ok = pd.Series(False, index=steps.index)
    for _, g in steps.groupby("recording", sort=False):
        ok[g.index] = confident_within(g["t"].to_numpy(), g["bout"].to_numpy(), window_s)
    return steps.assign(ok=ok)


def long_nongait_steps(seeds=LONG_SEEDS, minutes: float = 10.0) -> tuple[pd.DataFrame, pd.DataFrame]:
    """adaptive's steps (time, confidence, bout size) on non-gait recordings of ``minutes``."""
    steps, recs = [], []
    for kind in ("gestures", "desk"):
        for seed in seeds:
            rec = simulate_nongait(kind, duration_s=60.0 * minutes, seed=seed)
            t, c, b = _steps(rec)
            name = f"{kind}-long-{seed}"
            steps.append(pd.DataFrame({"recording": name, "t": t, "confidence": c, "bout": b, "matched": False}))
            recs.append({"recording": name, "source": "nongait", "group": kind, "person": "long", "seed": seed, "minutes": minutes})
    return pd.concat(steps, ignore_index=True), pd.DataFrame(recs)


def window_table(steps: pd.DataFrame, recs: pd.DataFrame, windows=WINDOWS) -> pd.DataFrame:
    """Per window: unsure % of real steps per tyrex motion and person, Oxford, slow walkers per split; confident
    non-gait steps per minute per kind and split (2-minute selection / held-out / fresh, 10-minute long)."""
    rows = []
    for w in windows:
        x = with_window(steps, w)
        row = {"window s": w}
        walk = x[x.source.isin(["tyrex", "slow-walk", "oxford", "ifsm-flat"])]
        for (source, group, person), g in walk.groupby(["source", "group", "person"]):
            if source in ("oxford", "ifsm-flat"):
                continue
            row[f"{group} {person} %"] = 100.0 * float((~g.ok).mean())
        for source in ("oxford", "ifsm-flat"):
            row[f"{source} %"] = 100.0 * float((~walk[walk.source == source].ok).mean())
        ng = x[x.source == "nongait"]
        for (kind, split), g in ng.groupby(["group", "person"]):
            minutes = recs[(recs.source == "nongait") & (recs.group == kind) & (recs.person == split)].minutes.sum()
            row[f"{kind} {split} /min"] = float(g.ok.sum()) / minutes
        rows.append(row)
    return pd.DataFrame(rows)


def choose_window(steps: pd.DataFrame, people, windows=WINDOWS, max_unsure: float = MAX_UNSURE) -> float:
    """The shortest window that calls at most ``max_unsure`` of the steps unsure in every walking group of the
    selection data: tyrex ``people`` per motion **and person** (AR apart) and the slow walkers of seeds 0-39 per
    position. (Per person, not pooled over people: a walker whose steps are often unsure is a failure even when the
    others dilute it; pooled, the three people give 20 s instead of 60 s.)"""
    sel = steps[
        ((steps.source == "tyrex") & steps.person.isin(people) & ~steps.group.isin(NO_REFERENCE))
        | ((steps.source == "slow-walk") & (steps.person == "selection"))
    ]
    for w in windows:
        x = with_window(sel, w)
        if all(float((~g.ok).mean()) <= max_unsure for _, g in x.groupby(["source", "group", "person"])):
            return float(w)
    return float(windows[-1])


def rule_table(steps: pd.DataFrame, recs: pd.DataFrame, window_s: float) -> pd.DataFrame:
    """The bout rule with ``window_s`` per source, group and split: unsure % of steps, recordings whose steps are
    mostly unsure (the stderr note of ``gaitml steps``), confident steps per minute."""
    x = with_window(steps, window_s)
    per = x.groupby("recording").agg(n=("ok", "size"), n_ok=("ok", "sum"))
    rr = recs.set_index("recording").join(per).fillna({"n": 0, "n_ok": 0})
    rr["mostly_unsure"] = (rr.n > 0) & (rr.n - rr.n_ok > rr.n / 2)
    rr["split"] = np.where(rr.source.isin(["tyrex", "oxford", "ifsm-flat"]), "all people", rr.person)
    out = []
    for (source, group, split), g in rr.groupby(["source", "group", "split"]):
        out.append(
            {
                "source": source,
                "group": group,
                "split": split,
                "recordings": len(g),
                "with steps": int((g.n > 0).sum()),
                "mostly unsure (note)": int(g.mostly_unsure.sum()),
                "steps": int(g.n.sum()),
                "unsure %": 100.0 * float((g.n - g.n_ok).sum() / max(g.n.sum(), 1)),
                "steps/min": float(g.n.sum() / g.minutes.sum()),
                "confident/min": float(g.n_ok.sum() / g.minutes.sum()),
                "confident/min worst": float((g.n_ok / g.minutes).max()),
            }
        )
    return pd.DataFrame(out)


def _md(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(str(c) for c in cols) + " |", "|" + "---|" * len(cols)]
    for r in df.itertuples(index=False):
        out.append("| " + " | ".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in r) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    """Print every table as markdown."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.step_confidence", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default="/tmp/unsure", help="cache of the per-step confidences ('' for none)")
    ap.add_argument("--threshold", type=float, help="also score this per-step confidence threshold on everything")
    ap.add_argument("--window", type=float, help="score the bout rule with this window (s) instead of the library's")
    a = ap.parse_args(argv)
    missing = [d for d in ("tyrex-attitude", "oxford-step-counter", "ifsm-flat-phone") if not (Path(a.data) / d).is_dir()]
    if missing:
        raise InputError(f"{a.data} has no {', '.join(missing)}: pass --data pointing at ../shared/data.")
    cache = Path(a.cache) if a.cache else None
    steps, recs = collect(Path(a.data), cache)
    every = steps
    steps = steps[steps.person != "fresh"]
    recs_all, recs = recs, recs[recs.person != "fresh"]
    if cache is not None and (cache / "long_steps.pkl").exists():
        long_s, long_r = pd.read_pickle(cache / "long_steps.pkl"), pd.read_pickle(cache / "long_recs.pkl")
    else:
        long_s, long_r = long_nongait_steps()
        if cache is not None:
            long_s.to_pickle(cache / "long_steps.pkl")
            long_r.to_pickle(cache / "long_recs.pkl")
    every = pd.concat([every, long_s.merge(long_r, on="recording")], ignore_index=True)
    recs_all = pd.concat([recs_all, long_r], ignore_index=True)

    print(f"\n## The bout rule: a step is confident when a bout of >= {SHORT_BOUT_STEPS} steps lies within W s of it\n")
    print("Unsure % of real steps (tyrex per motion and person, simulated slow walkers per split, Oxford, IFSM flat-held);")
    print("confident non-gait steps per minute (2-minute recordings: selection 0-39, held-out 100-129, fresh 300-359;")
    print(f"10-minute recordings, seeds {LONG_SEEDS[0]}-{LONG_SEEDS[-1]}).\n")
    wt = window_table(every, recs_all)
    print(_md(wt.set_index("window s").T.reset_index().rename(columns={"index": "group"})))
    print("\nWindow chosen per left-out person (shortest with <= 2 % unsure in every selection walking group):\n")
    rows = []
    for out in (*PEOPLE, None):
        sel = [p for p in PEOPLE if p != out]
        w = choose_window(every, sel)
        row = {"left out": out or "none (shipped)", "window s": w}
        if out is not None:
            x = with_window(every[(every.source == "tyrex") & (every.person == out)], w)
            for motion, g in x.groupby("group"):
                row[f"{motion} unsure %"] = 100.0 * float((~g.ok).mean())
        rows.append(row)
    print(_md(pd.DataFrame(rows)))
    shipped = CONFIDENT_WINDOW_S if a.window is None else a.window
    print(f"\n## The rule as shipped (window {shipped:g} s), per source\n")
    print(_md(rule_table(every, recs_all, shipped)))

    print("\n# Per-step confidence thresholds (not shipped: they do not separate)\n")
    sim_sel = steps[(steps.source.isin(["slow-walk", "nongait"])) & (steps.person == "selection")]

    print("\n## Trade-off: unsure share of real steps (%) against confident non-gait steps per minute\n")
    rules = [(float(t), 0) for t in (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5)]
    rules += [(0.0, n) for n in (5, 6, 7, 8, SHORT_BOUT_STEPS)] + [(0.1, n) for n in (6, 8, SHORT_BOUT_STEPS)]
    print(_md(tradeoff(steps, recs, rules)))

    print("\n## Thresholds chosen by the rule (largest with <= 2 % unsure steps in every walking group of the selection data)\n")
    chosen = {}
    rows = []
    for out in (*PEOPLE, None):
        sel_people = [p for p in PEOPLE if p != out]
        ty = steps[(steps.source == "tyrex") & steps.person.isin(sel_people)]
        groups = walking_groups(pd.concat([ty, sim_sel]))
        t = choose_threshold(groups)
        chosen[out] = t
        binding = min(groups, key=lambda k: np.quantile(groups[k], MAX_UNSURE) if len(groups[k]) else np.inf)
        rows.append(
            {"left out": out or "none (all three)", "selection people": "+".join(sel_people), "threshold": t, "binding group": binding}
        )
    print(_md(pd.DataFrame(rows)))

    rec_rows_by_t = {}
    for out in PEOPLE:
        t = chosen[out]
        print(f"\n## Left out {out}: threshold {t:.2f} (chosen on the other two and seeds 0-39)\n")
        ty = steps[steps.source == "tyrex"]
        ty = ty.assign(split=np.where(ty.person == out, "held out", "selection"))
        print(_md(unsure_table(ty, t, ["group", "split"])))
    for t in sorted({chosen[None], 0.5} | ({a.threshold} if a.threshold is not None else set())):
        print(f"\n## Threshold {t:.2f}: every source\n")
        print("Real and simulated walking, per group (tyrex: per motion and person):\n")
        walk = steps[steps.source != "nongait"]
        print(_md(unsure_table(walk[walk.source == "tyrex"], t, ["group", "person"])))
        print()
        print(_md(unsure_table(walk, t, ["source", "group"])))
        print()
        print(_md(unsure_table(walk[walk.source.isin(["slow-walk"])], t, ["group", "person"])))
        rr = per_recording(steps, recs, t)
        rec_rows_by_t[t] = rr
        print("\nNo gait, per minute (held-out seeds 100-129, then selection seeds 0-39):\n")
        print(_md(nongait_summary(rr, "held-out")))
        print()
        print(_md(nongait_summary(rr, "selection")))
        walks = rr[rr.source != "nongait"]
        flag = walks.groupby(["source", "group"]).agg(recordings=("n", "size"), mostly_unsure=("mostly_unsure", "sum")).reset_index()
        print("\nWalking recordings whose steps are MOSTLY unsure (the stderr note would fire):\n")
        print(_md(flag))
        bad = walks[walks.mostly_unsure]
        if len(bad):
            print("\n" + "\n".join(f"- {r.recording}: {int(r.n_confident)} of {int(r.n)} confident" for r in bad.itertuples()))
    # leave-one-person-out: the held-out person's figures at the threshold chosen without them
    print("\n## Leave-one-person-out summary (tyrex, each person scored at the threshold chosen without them)\n")
    rows = []
    for out in PEOPLE:
        t = chosen[out]
        g = steps[(steps.source == "tyrex") & (steps.person == out)]
        for motion, gg in g.groupby("group"):
            c = gg["confidence"].to_numpy()
            rows.append({"left out": out, "threshold": t, "motion": motion, "steps": len(c), "unsure %": 100.0 * float(np.mean(c < t))})
    lo = pd.DataFrame(rows)
    print(_md(lo.pivot_table(index="motion", columns="left out", values="unsure %").reset_index()))
    print("\nOxford and IFSM flat-held were never used to choose; simulator held-out seeds 100-129 at each left-out threshold:\n")
    rows = []
    for out in PEOPLE:
        t = chosen[out]
        rr = per_recording(steps, recs, t)
        ng = nongait_summary(rr, "held-out")
        sim = steps[(steps.source == "slow-walk") & (steps.person == "held-out")]
        row = {"threshold (tyrex without " + out + ")": t}
        for kind, v in zip(ng["kind"], ng["confident/min mean"], strict=True):
            row[f"{kind} confident/min"] = float(v)
        for p, gg in sim.groupby("group"):
            row[f"slow {p} unsure %"] = 100.0 * float(np.mean(gg.confidence < t))
        ox = steps[steps.source == "oxford"]
        row["oxford unsure %"] = 100.0 * float(np.mean(ox.confidence < t))
        rows.append(row)
        print(", ".join(f"{k} {v:.3f}" for k, v in row.items()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
