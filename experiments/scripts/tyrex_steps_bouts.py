"""Adaptive's walking-episode bout rule (stage 5b) chosen leave-one-person-out on the tyrex recordings (issue 30).

The joint helper found about half of Guillaume's missed Texting / Phoning steps picked by ``adaptive`` and then dropped
with their bouts by the short-bout, minimum-bout and edge rules (``experiments/reports/tyrex-steps.md``). Stage 5b
(``episode_gap_ratio``, ``max_bout_interval_cv``, ``edge_interval_match``; :func:`gaitml.steps.adaptive._episode_keep`)
keeps a bout those rules drop when its step intervals are regular and a bout beside it (within a few step periods,
one walking episode) passes on its own. Its settings are chosen over :data:`GRID` under the adoption rule fixed before
measuring (the report's "bouts helper" section):

- *admissible*: on the simulated non-gait selection seeds 0-39 no more raw AND no more confident steps per minute
  (:func:`gaitml.steps.confident_steps`) than today (off), gestures and desk;
- per person left out, the admissible setting best on the other two (``tyrex_steps_lopo._score``) is scored on the
  third; B1-B3 on the pooled held-out rows (as the joint helper's J1-J3); for the setting that would ship (admissible,
  best on all three): B4 held-out non-gait seeds 100-119 raw and confident steps/min not above today's, B5 slow walkers'
  held-out seeds not below, B6 Oxford and IFSM mean count accuracy not below (B7, throughput: ``python -m
  benchmarks.steps``).

``--dropped`` describes the bouts today's rules drop (Texting and Phoning, whose reference counts steps): their length,
interval regularity, confidence, the gap to the nearest kept bout, and how many of their steps a reference step
matches. Every detector run is cached per setting (pickles in ``--cache``; empty it after any change to ``gaitml``).

    python -m experiments.scripts.tyrex_steps_bouts [--data ../shared/data] [--cache /tmp/bouts] [--round 3]  # ~20 min, seconds cached
    python -m experiments.scripts.tyrex_steps_bouts --check G5,C0.1,edge [--cache /tmp/bouts]       # B4-B6 for one setting
    python -m experiments.scripts.tyrex_steps_bouts --dropped                                        # today's dropped bouts
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_joint import (
    HELDOUT_SEEDS,
    SELECTION_SEEDS,
    STEP_MOTIONS,
    _cached,
    f1,
    frame,
    nongait_recordings,
    per_motion,
    step_times,
)
from experiments.scripts.tyrex_steps_joint import lopo as joint_lopo
from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED, _load, _score

OFF = "off"
#: today's (before round 3's adoption) stage 5b: off, spelled out so that "off" stays today's rules whatever the defaults
OFF_SETTING = {"episode_gap_ratio": 0.0}


def _setting(gap: float, cv: float, edge: bool, walk: int, before: bool = True) -> dict:
    return {
        "episode_gap_ratio": gap,
        "max_bout_interval_cv": cv,
        "edge_interval_match": edge,
        "episode_walk_steps": walk,
        "episode_before_gait_check": before,
    }


def grid_of(round_: int) -> dict[str, dict]:
    """The grid fixed before measuring (report, "bouts helper"): off and G in {3, 5} x C in {0.1, 0.2} x edge rule.
    Round 1: any bout that passes the rules alone is walking (``episode_walk_steps=0``); round 2: a bout of at least
    ten kept steps (the library's ``EPISODE_WALK_STEPS``); rounds 1-2 run stage 5b before the gait check
    (``episode_before_gait_check``). Round 3 (report, "bouts2 helper"): round 2's settings after the gait check, with a
    gyroscope only (keys carry ``,r3``)."""
    walk = 0 if round_ == 1 else 10
    suffix = {1: ",r1", 2: "", 3: ",r3"}[round_]
    out: dict[str, dict] = {OFF: dict(OFF_SETTING)}
    for g in (3, 5):
        for c in (0.1, 0.2):
            for e in (False, True):
                key = f"G{g},C{c}" + (",edge" if e else "") + suffix
                out[key] = _setting(float(g), c, e, walk, before=round_ < 3)
    return out


GRID: dict[str, dict] = {
    **grid_of(2),
    **{k: v for k, v in grid_of(1).items() if k != OFF},
    **{k: v for k, v in grid_of(3).items() if k != OFF},
}
KINDS = ("gestures", "desk")
#: a detected step matches a reference step within this (s), as the joint helper's ``--misses``
COVER_S = 0.45


def nongait_rates(recs: dict, seeds, **kw) -> dict[str, float]:
    """Adaptive's mean (and worst) raw and confident steps per minute on the gestures and desk recordings."""
    from gaitml.steps import confident_steps, get_detector

    out = {}
    for kind in KINDS:
        raw, conf = [], []
        for s in seeds:
            rec = recs[(kind, s)]
            st = get_detector("adaptive", **kw).detect(rec).steps_
            minutes = rec.duration_s / 60
            raw.append(len(st) / minutes)
            conf.append(float(np.sum(confident_steps(st)[0])) / minutes if len(st) else 0.0)
        out[kind], out[f"{kind}_max"] = float(np.mean(raw)), float(np.max(raw))
        out[f"{kind}_confident"] = float(np.mean(conf))
    return out


def admissible_set(rates: dict[str, dict[str, float]]) -> set[str]:
    """Settings with no more raw and no more confident steps/min than off on gestures and desk (off is always in)."""
    ref = rates[OFF]
    keys = [*KINDS, *(f"{k}_confident" for k in KINDS)]
    return {k for k, r in rates.items() if all(r[c] <= ref[c] + 1e-9 for c in keys)}


def choose(grid: dict[str, pd.DataFrame], allowed: set[str], people=None) -> str:
    """The allowed setting with the best score on ``people`` (all if None); off wins ties, then grid order."""

    def s(k):
        d = grid[k] if people is None else grid[k][grid[k]["person"].isin(people)]
        return _score(d)

    return max((k for k in GRID if k in allowed and k in grid), key=s)


def lopo(grid: dict[str, pd.DataFrame], allowed: set[str], adfsm: pd.DataFrame | None = None) -> tuple[str, dict[str, bool], list]:
    """Per person left out: the allowed setting chosen on the other two, its held-out figures, and B1-B3
    (:func:`experiments.scripts.tyrex_steps_joint.lopo` with this grid's off setting, choice and names)."""
    return joint_lopo(grid, allowed, adfsm, off_key=OFF, chooser=choose, label=str, rule="B", off_label="off")


def insample(grid: dict[str, pd.DataFrame], rates: dict[str, dict[str, float]], allowed: set[str]) -> str:
    """Every setting on all three people, best first, with its non-gait rates on the selection seeds."""
    cols = ["setting", "admissible", "gestures /min (confident)", "desk /min (confident)", "score", *SCORED, "F1 Texting", "F1 Phoning"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    allp = {k: _score(v) for k, v in grid.items()}
    for k in sorted(allp, key=allp.get, reverse=True):
        per, r = per_motion(grid[k]), rates[k]
        cells = [k, "yes" if k in allowed else "no"]
        cells += [f"{r[kind]:.3f} ({r[kind + '_confident']:.3f})" for kind in KINDS]
        cells += [f"{allp[k]:.4f}", *(f"{per[m]:.3f}" for m in SCORED), *(f"{f1(grid[k], m):.3f}" for m in STEP_MOTIONS)]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def per_person(runs: dict[str, pd.DataFrame]) -> str:
    """Mean count accuracy per motion and person for each named run (in sample)."""
    cols = ["run", "person", *SCORED, "score"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for label, df in runs.items():
        for person in PEOPLE:
            d = df[df["person"] == person]
            per = per_motion(d)
            out.append("| " + " | ".join([label, person, *(f"{per[m]:.3f}" for m in SCORED), f"{_score(d):.4f}"]) + " |")
    return "\n".join(out)


def slow_walkers(key: str, cache: Path | None, params: dict | None = None) -> dict[str, list[float]]:
    """Adaptive's count accuracy per position on the simulated slow walkers' held-out seeds at setting ``key``
    (``params``: its keywords when ``key`` is not in :data:`GRID`; the cache is keyed by ``key``)."""
    from experiments.scripts.slow_walks import POSITIONS, count_accuracy, slow_recording
    from gaitml.steps import get_detector

    kw = GRID[key] if params is None else params

    def make():
        out = {}
        for position in POSITIONS:
            acc = []
            for s in HELDOUT_SEEDS:
                rec = slow_recording(s, position)
                acc.append(count_accuracy(rec.reference["n_steps_true"], len(get_detector("adaptive", **kw).detect(rec).steps_)))
            out[position] = acc
        return out

    return _cached(cache, f"slow_{key}", make)


def no_gyroscope(data: str | Path, key: str, params: dict | None = None, off_params: dict | None = None) -> dict[str, float]:
    """Oxford and IFSM (no gyroscope): files with a true count, mean count accuracy off and at ``key``, files changed
    (``params`` / ``off_params``: the two runs' keywords when not :data:`GRID`'s)."""
    kw1 = GRID[key] if params is None else params
    kw0 = GRID[OFF] if off_params is None else off_params
    from experiments.scripts.slow_walks import count_accuracy
    from gaitml.io.ifsm import read_ifsm_xlsx
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder
    from gaitml.steps import get_detector

    root = Path(data)
    recs = []
    for f in list_oxford_folders(root / "oxford-step-counter"):
        r = read_oxford_folder(f)
        recs.extend(r if isinstance(r, list) else [r])
    recs += [read_ifsm_xlsx(f) for f in sorted((root / "ifsm-flat-phone").rglob("*.xlsx"))]
    a0, a1, changed, n = [], [], 0, 0
    for r in recs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            t0 = get_detector("adaptive", **kw0).detect(r).steps_["t_peak_s"].to_numpy()
            t1 = get_detector("adaptive", **kw1).detect(r).steps_["t_peak_s"].to_numpy()
        changed += int(not np.array_equal(t0, t1))
        true = r.reference.get("n_steps_true") if r.reference else None
        if true is not None:
            n += 1
            a0.append(count_accuracy(int(true), len(t0)))
            a1.append(count_accuracy(int(true), len(t1)))
    return {"files": len(recs), "counted": n, "off": float(np.mean(a0)), "setting": float(np.mean(a1)), "changed": changed}


def heldout_checks(key: str, data: str | Path, cache: Path | None) -> tuple[list[str], dict[str, bool]]:
    """B4-B6 for setting ``key`` against off: held-out non-gait seeds, slow walkers' held-out seeds, Oxford and IFSM."""
    ho = nongait_recordings(HELDOUT_SEEDS, cache)
    h0 = _cached(cache, "nongait_heldout_off", lambda: nongait_rates(ho, HELDOUT_SEEDS, **GRID[OFF]))
    h1 = _cached(cache, f"nongait_heldout_{key}", lambda: nongait_rates(ho, HELDOUT_SEEDS, **GRID[key]))
    s0, s1 = slow_walkers(OFF, cache), slow_walkers(key, cache)
    ox = no_gyroscope(data, key)
    checks = {
        "B4": all(h1[c] <= h0[c] + 1e-9 for kind in KINDS for c in (kind, f"{kind}_confident")),
        "B5": all(np.mean(s1[p]) >= np.mean(s0[p]) - 1e-12 for p in s0),
        # round 3 promises the step table of a recording without a gyroscope is today's: no file may change
        "B6": ox["setting"] >= ox["off"] - 1e-12 and (ox["changed"] == 0 or not key.endswith(",r3")),
    }
    lines = [f"Held-out checks for {key} (off -> it):"]
    for kind in KINDS:
        lines.append(
            f"- non-gait {kind}, seeds 100-119: raw {h0[kind]:.3f} (worst {h0[kind + '_max']:.1f}) -> {h1[kind]:.3f} "
            f"(worst {h1[kind + '_max']:.1f}) steps/min; confident {h0[kind + '_confident']:.3f} -> {h1[kind + '_confident']:.3f}"
        )
    for p in s0:
        lines.append(
            f"- slow walkers {p}, seeds 100-119: {np.mean(s0[p]):.3f} (worst {np.min(s0[p]):.3f}) -> {np.mean(s1[p]):.3f} (worst {np.min(s1[p]):.3f})"
        )
    lines.append(
        f"- Oxford and IFSM: {ox['files']} files ({ox['counted']} with a true count), mean count accuracy {ox['off']:.4f} -> "
        f"{ox['setting']:.4f}; files whose step times change: {ox['changed']}"
    )
    return lines, checks


def bout_of(t: np.ndarray, period: np.ndarray) -> np.ndarray:
    """Bout number of each step time (as adaptive: an interval over 2 local periods ends a bout)."""
    from gaitml.steps.adaptive import BOUT_GAP_RATIO

    if len(t) == 0:
        return np.zeros(0, dtype=np.int64)
    gap = np.diff(t) > BOUT_GAP_RATIO * np.maximum(period[:-1], period[1:])
    return np.r_[0, np.cumsum(gap)].astype(np.int64)


def dropped_bouts(t_all: np.ndarray, period: np.ndarray, conf: np.ndarray, kept: np.ndarray, ref: np.ndarray) -> pd.DataFrame:
    """The bouts of ``t_all`` (steps found with every bout rule off) none of whose steps is in ``kept`` (today's steps):
    per bout its steps, interval CV, median confidence, how many of its steps a reference step matches within
    :data:`COVER_S`, and the gap to the nearest bout with a kept step, in local step periods (inf if none)."""
    cols = ["steps", "interval_cv", "confidence", "matched", "gap_periods"]
    if len(t_all) == 0:
        return pd.DataFrame(columns=cols)
    bout = bout_of(t_all, period)
    is_kept = np.isin(np.round(t_all, 6), np.round(kept, 6))
    kept_bout = np.bincount(bout, weights=is_kept.astype(float)) > 0
    rows = []
    for b in np.flatnonzero(~kept_bout):
        i = np.flatnonzero(bout == b)
        d = np.diff(t_all[i])
        cv = float(np.std(d) / np.mean(d)) if len(d) >= 2 else (abs(d[0] - period[i[0]]) / period[i[0]] if len(d) == 1 else np.inf)
        others = t_all[is_kept]
        gap = (
            float(np.min(np.abs(np.r_[others - t_all[i[0]], others - t_all[i[-1]]]))) / float(np.median(period[i]))
            if len(others)
            else np.inf
        )
        matched = int(np.sum(np.min(np.abs(t_all[i][:, None] - ref[None, :]), axis=1) <= COVER_S)) if len(ref) else 0
        rows.append({"steps": len(i), "interval_cv": cv, "confidence": float(np.median(conf[i])), "matched": matched, "gap_periods": gap})
    return pd.DataFrame(rows, columns=cols)


def _steps_with_bout_rules_off(rec) -> pd.DataFrame:
    from gaitml.steps import get_detector

    return get_detector("adaptive", short_bout_steps=0, min_bout_steps=1, edge_confidence_ratio=0.0, **OFF_SETTING).detect(rec).steps_


def dropped_table(items: list[dict]) -> str:
    """Today's dropped bouts on Texting and Phoning per person: counts by interval CV and gap to the nearest kept bout."""
    from gaitml.steps import get_detector

    rows = []
    for it in items:
        if it["motion"] not in STEP_MOTIONS:
            continue
        ref = np.asarray(it["ref"]["t_s"])
        for r in it["recs"]:
            t0 = float(r.meta.get("t0_original_s", 0.0))
            a = _steps_with_bout_rules_off(r)
            k = get_detector("adaptive", **OFF_SETTING).detect(r).steps_
            ta = t0 + a["t_peak_s"].to_numpy()
            inside = (ta >= it["ref"]["t_first_s"]) & (ta <= it["ref"]["t_last_s"])
            df = dropped_bouts(
                ta[inside], a["period_s"].to_numpy()[inside], a["confidence"].to_numpy()[inside], t0 + k["t_peak_s"].to_numpy(), ref
            )
            df["motion"], df["person"] = it["motion"], it["person"]
            rows.append(df)
    d = pd.concat(rows, ignore_index=True)
    cols = [
        "motion",
        "person",
        "dropped bouts",
        "their steps (matched by a reference step)",
        "steps per bout: 1 / 2-3 / 4-9 / 10+",
        "interval CV <= 0.1 / 0.1-0.2 / > 0.2 (steps)",
        "gap to a kept bout <= 3 / 3-5 / > 5 periods (steps)",
        "median confidence",
    ]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for motion in STEP_MOTIONS:
        for person in PEOPLE:
            x = d[(d["motion"] == motion) & (d["person"] == person)]
            n = x["steps"]
            sizes = [int((n == 1).sum()), int(n.between(2, 3).sum()), int(n.between(4, 9).sum()), int((n >= 10).sum())]
            cv = x["interval_cv"]
            cvs = [int(n[cv <= 0.1].sum()), int(n[(cv > 0.1) & (cv <= 0.2)].sum()), int(n[cv > 0.2].sum())]
            g = x["gap_periods"]
            gaps = [int(n[g <= 3].sum()), int(n[(g > 3) & (g <= 5)].sum()), int(n[g > 5].sum())]
            cells = [motion, person, str(len(x)), f"{int(n.sum())} ({int(x['matched'].sum())})", " / ".join(map(str, sizes))]
            cells += [" / ".join(map(str, cvs)), " / ".join(map(str, gaps)), f"{x['confidence'].median():.2f}" if len(x) else "-"]
            out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    """Print admissibility, the leave-one-person-out choice with B1-B3, in sample, and B4-B6 for the setting that would ship."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_bouts", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default=None, help="folder for the per-setting detector runs and simulated recordings (pickles)")
    ap.add_argument("--check", default=None, help=f"only B4-B6 for one setting, one of {', '.join(GRID)}")
    ap.add_argument("--dropped", action="store_true", help="describe the bouts today's rules drop (Texting, Phoning)")
    ap.add_argument("--round", type=int, choices=(1, 2, 3), default=2, help="the grid of round 1, 2 or 3 (report)")
    a = ap.parse_args(argv)
    if a.check is not None and a.check not in GRID:
        print(f"error: --check must be one of {', '.join(GRID)}, got {a.check!r}", file=sys.stderr)
        return 2
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    cache = Path(a.cache) if a.cache else None
    if a.dropped:
        print("Bouts today's rules drop (found with every bout rule off, none of their steps kept), Texting and Phoning:\n")
        print(dropped_table(_load(a.data)))
        return 0
    if a.check is not None:
        lines, checks = heldout_checks(a.check, a.data, cache)
        print("\n".join(lines))
        print("\nChecks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
        return 0
    ng = nongait_recordings(SELECTION_SEEDS, cache)
    keys = list(grid_of(a.round))
    rates = {k: _cached(cache, f"nongait_sel_{k}", lambda k=k: nongait_rates(ng, SELECTION_SEEDS, **GRID[k])) for k in keys}
    allowed = admissible_set(rates)
    items = _load(a.data)
    grid = {}
    for k in keys:
        grid[k] = frame(items, _cached(cache, f"tyrex_{k}" if k != OFF else "tyrex_off_off", lambda k=k: step_times(items, **GRID[k])))
        r = rates[k]
        print(
            f"{k}: {_score(grid[k]):.4f}, gestures {r['gestures']:.3f} ({r['gestures_confident']:.3f}), desk {r['desk']:.3f}",
            file=sys.stderr,
        )
    adfsm = frame(items, _cached(cache, "tyrex_adfsm", lambda: step_times(items, "adfsm")))
    r0 = rates[OFF]
    print(
        f"Admissible: no more raw and confident steps/min than off on the simulated non-gait seeds 0-39 (gestures "
        f"{r0['gestures']:.3f} ({r0['gestures_confident']:.3f}), desk {r0['desk']:.3f} ({r0['desk_confident']:.3f})): "
        f"{len(allowed)} of {len(rates)} settings.\n"
    )
    print("Leave-one-person-out, admissible settings only (cells: held out with the chosen setting (off)):\n")
    table, checks, chosen = lopo(grid, allowed, adfsm)
    print(table)
    ship = choose(grid, allowed)
    print(f"\nSetting that would ship (admissible, best on all three people): {ship} ({_score(grid[ship]):.4f})")
    print("\nThe same with every setting allowed (non-gait not weighed; for the record):\n")
    print(lopo(grid, set(grid), adfsm)[0])
    print("\nIn sample (all three people), best first:\n")
    print(insample(grid, rates, allowed))
    runs = {"off (today)": grid[OFF], **{k: grid[k] for k in dict.fromkeys([*chosen, ship]) if k != OFF}, "adfsm": adfsm}
    print("\nPer person, in sample:\n")
    print(per_person(runs))
    if ship != OFF:
        lines, more = heldout_checks(ship, a.data, cache)
        checks.update(more)
        print("\n".join(["", *lines]))
    print("\nAdoption checks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
