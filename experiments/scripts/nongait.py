"""Steps without gait: the gait-evidence test (``gaitml.steps._gait_evidence``) per detector, before and after.

Four tables, each with the test off and on in the same run:

1. **No gait** (``gaitml.simulate.nongait``: gestures while standing, a phone handled at a desk; 120 s each):
   steps per minute per detector. Seeds 0-39 were looked at while choosing the test and its threshold (0-7 first,
   8-39 after the first held-out run, see the report); seeds 100-119 are held out.
2. **Slow walkers** (``experiments.scripts.slow_walks``: 0.8-1.2 steps/s, hand flat / tilted / front pocket): count
   accuracy of ``adaptive``, selection seeds 0-7 and held-out seeds 100-119.
3. **tyrex** (``../shared/data/tyrex-attitude``): count accuracy against the motion-capture count
   (``experiments.scripts.tyrex_steps.mocap_steps``) per motion and person, every detector. The threshold was
   checked on Guillaume and Jakob; Thibaud is held out.
4. **Oxford** (no gyroscope): the test cannot run; the counts with it on and off are compared to show they agree.

And the throughput of ``adaptive`` with the test off and on, on a one-hour simulated walk with a gyroscope
(interleaved repeats, best of each; CPU time of this process).

    python -m experiments.scripts.nongait [--data ../shared/data] [--skip-tyrex] [--skip-oxford]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import gait_check_recording

SELECTION_SEEDS = tuple(range(40))
HELDOUT_SEEDS = tuple(range(100, 120))
DETECTORS = ("adaptive", "single-peak", "ifsm", "adfsm", "autocorr", "fsm-selflearn")
PEOPLE_SELECTION = ("Guillaume", "Jakob")


def count_both(name: str, rec) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The detector's steps on ``rec`` without and with the gait-evidence test (as ``gaitml steps`` runs it)."""
    if name == "adaptive":
        return get_detector(name, gait_check=False).detect(rec).steps_, get_detector(name).detect(rec).steps_
    st = get_detector(name).detect(rec).steps_
    return st, gait_check_recording(st, rec)


def nongait_table(seeds) -> pd.DataFrame:
    """Steps per minute per kind and detector, test off / on (mean and worst over the seeds)."""
    rows = []
    for kind in ("gestures", "desk"):
        per: dict[str, list] = {}
        for seed in seeds:
            rec = simulate_nongait(kind, duration_s=120, seed=seed)
            minutes = rec.duration_s / 60.0
            for d in DETECTORS:
                off, on = count_both(d, rec)
                per.setdefault(d, []).append((len(off) / minutes, len(on) / minutes))
                if d == "adaptive":
                    c_off = float(np.sum(off["confidence"] >= 0.5)) / minutes
                    c_on = float(np.sum(on["confidence"] >= 0.5)) / minutes
                    per.setdefault("adaptive, confidence >= 0.5", []).append((c_off, c_on))
        for d, v in per.items():
            a = np.asarray(v)
            rows.append(
                {
                    "kind": kind,
                    "detector": d,
                    "off_mean": a[:, 0].mean(),
                    "on_mean": a[:, 1].mean(),
                    "off_max": a[:, 0].max(),
                    "on_max": a[:, 1].max(),
                }
            )
    return pd.DataFrame(rows)


def slow_table(seeds) -> pd.DataFrame:
    """Count accuracy of adaptive on the simulated slow walkers, test off / on."""
    from experiments.scripts.slow_walks import POSITIONS, count_accuracy, slow_recording

    rows = []
    for position in POSITIONS:
        acc = []
        for seed in seeds:
            rec = slow_recording(seed, position)
            n_true = rec.reference["n_steps_true"]
            off, on = count_both("adaptive", rec)
            acc.append((count_accuracy(n_true, len(off)), count_accuracy(n_true, len(on))))
        a = np.asarray(acc)
        rows.append(
            {
                "position": position,
                "off_mean": a[:, 0].mean(),
                "on_mean": a[:, 1].mean(),
                "off_worst": a[:, 0].min(),
                "on_worst": a[:, 1].min(),
            }
        )
    return pd.DataFrame(rows)


def tyrex_rows(data: Path) -> pd.DataFrame:
    """One row per tyrex recording: motion, person, mocap count, and each detector's count with the test off / on."""
    from experiments.scripts.tyrex_steps import in_reference_span, truth_clock_s, tyrex_walks

    rows = []
    for walk in tyrex_walks(data):
        ref = walk["ref"]
        row = {"recording": walk["name"], "motion": walk["motion"], "person": walk["person"], "mocap_steps": ref["n_steps"]}
        for d in DETECTORS:
            n_off = n_on = 0
            for r in walk["recs"]:
                for st, which in zip(count_both(d, r), ("off", "on"), strict=True):
                    k = int(np.sum(in_reference_span(truth_clock_s(st, r), ref)))
                    if which == "off":
                        n_off += k
                    else:
                        n_on += k
            row[f"{d}_off"], row[f"{d}_on"] = n_off, n_on
        rows.append(row)
        print(f"tyrex {walk['name']}", file=sys.stderr, flush=True)
    return pd.DataFrame(rows)


def tyrex_summary(df: pd.DataFrame) -> pd.DataFrame:
    """Mean count accuracy per motion (AR apart: no reliable reference) and per person group, test off / on."""
    out = []
    for motion, g in df.groupby("motion"):
        for who, gg in (
            ("all", g),
            ("Guillaume+Jakob", g[g.person.isin(PEOPLE_SELECTION)]),
            ("Thibaud (held out)", g[~g.person.isin(PEOPLE_SELECTION)]),
        ):
            row = {"motion": motion, "people": who, "n": len(gg)}
            for d in DETECTORS:
                for w in ("off", "on"):
                    row[f"{d}_{w}"] = (
                        float(np.mean(1.0 - np.abs(gg[f"{d}_{w}"] - gg["mocap_steps"]) / gg["mocap_steps"])) if len(gg) else np.nan
                    )
            out.append(row)
    return pd.DataFrame(out)


def oxford_check(data: Path) -> pd.DataFrame:
    """Adaptive's count on each Oxford recording with the test off and on (no gyroscope: they must agree)."""
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder

    rows = []
    for folder in list_oxford_folders(data / "oxford-step-counter"):
        rec = read_oxford_folder(folder)
        off, on = count_both("adaptive", rec)
        rows.append({"recording": folder.name, "gyroscope": rec.gyr is not None, "off": len(off), "on": len(on)})
    return pd.DataFrame(rows)


def throughput(repeats: int = 5) -> dict:
    """Samples per CPU second of adaptive with the test off and on, a one-hour simulated walk with a gyroscope."""
    from gaitml.simulate import Subject, simulate_recording

    rec = simulate_recording(Subject.random(np.random.default_rng(5), subject="BENCH"), modes=["walk"], duration_s=3600, seed=5)
    best = {"off": np.inf, "on": np.inf}
    for _ in range(repeats):
        for w, det in (("off", get_detector("adaptive", gait_check=False)), ("on", get_detector("adaptive"))):
            t0 = time.process_time()
            det.detect(rec)
            best[w] = min(best[w], time.process_time() - t0)
    return {w: rec.n_samples / s for w, s in best.items()} | {"n_samples": rec.n_samples}


def md_table(df: pd.DataFrame) -> str:
    """A markdown table of ``df``; floats with three decimals."""
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in df.itertuples(index=False):
        out.append("| " + " | ".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in r) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    """Print the tables as markdown."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.nongait", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--skip-tyrex", action="store_true")
    ap.add_argument("--skip-oxford", action="store_true")
    ap.add_argument("--tyrex-csv", metavar="FILE", help="write the per-recording tyrex counts")
    a = ap.parse_args(argv)
    data = Path(a.data)
    tp = throughput()
    print(f"\nadaptive throughput, one-hour simulated walk ({tp['n_samples']} samples), best of 5 CPU times:")
    print(f"gait check off {tp['off'] / 1e6:.2f} M samples/s, on {tp['on'] / 1e6:.2f} M samples/s")
    for name, seeds in (("selection seeds 0-39", SELECTION_SEEDS), ("held-out seeds 100-119", HELDOUT_SEEDS)):
        print(f"\nNo gait, steps per minute, {name} (gait check off / on)\n")
        print(md_table(nongait_table(seeds)))
    for name, seeds in (("selection seeds 0-7", tuple(range(8))), ("held-out seeds 100-119", HELDOUT_SEEDS)):
        print(f"\nSlow walkers, adaptive count accuracy, {name} (gait check off / on)\n")
        print(md_table(slow_table(seeds)))
    if not a.skip_oxford:
        ox = oxford_check(data)
        print(
            f"\nOxford: {len(ox)} recordings, with a gyroscope: {int(ox.gyroscope.sum())}; adaptive counts equal with the test off and on: "
            f"{int((ox.off == ox.on).sum())} of {len(ox)} (total {int(ox.off.sum())} / {int(ox.on.sum())})"
        )
    if not a.skip_tyrex:
        ty = tyrex_rows(data)
        if a.tyrex_csv:
            ty.to_csv(a.tyrex_csv, index=False)
        print("\ntyrex, count accuracy against the motion-capture count, mean over recordings (gait check off / on)\n")
        print(md_table(tyrex_summary(ty)))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
