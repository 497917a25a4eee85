"""Leave-one-person-out choice of adaptive's gyroscope settings on the tyrex recordings (issue 30).

``adaptive``'s gyroscope check (``gyro_min_rms_rads``, ``gyro_phase_correlation``) has two settings chosen
on these recordings. For each person left out, every pair of the grid is scored on the other two people (the
mean over the seven scored motions of the mean count accuracy against the motion-capture count of
:mod:`experiments.scripts.tyrex_steps`; AR has no reliable reference and is left out), the best pair is
chosen, and the left-out person is scored with it, next to the accelerometer alone (``use_gyroscope=False``).
The last table is the choice on all three people (in sample): the library's defaults.

    python -m experiments.scripts.tyrex_steps_lopo [--data ../shared/data]    # about 2 min
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps import tyrex_walks

MIN_RMS_GRID = (0.05, 0.2, 0.5, 1.0)
PHASE_GRID = (0.3, 0.5, 0.7)
SCORED = ("Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging", "RunningHand", "RunningPocket")
PEOPLE = ("Guillaume", "Jakob", "Thibaud")


def _load(data: str | Path) -> list[dict]:
    return list(tyrex_walks(data, SCORED))


def _counts(items: list[dict], **params) -> pd.DataFrame:
    from gaitml.steps import get_detector

    rows = []
    for it in items:
        n = 0
        for r in it["recs"]:
            st = get_detector("adaptive", **params).detect(r).steps_
            tt = float(r.meta.get("t0_original_s", 0.0)) + st["t_peak_s"].to_numpy()
            n += int(np.sum((tt >= it["ref"]["t_first_s"]) & (tt <= it["ref"]["t_last_s"])))
        n_ref = it["ref"]["n_steps"]
        rows.append(
            {"recording": it["name"], "motion": it["motion"], "person": it["person"], "n": n, "acc": 1 - abs(n - n_ref) / max(n_ref, 1)}
        )
    return pd.DataFrame(rows)


def _score(df: pd.DataFrame) -> float:
    """Mean over motions of the mean count accuracy (each motion weighs the same)."""
    return float(df.groupby("motion")["acc"].mean().mean())


def main(argv: list[str] | None = None) -> int:
    """Print the per-fold choice and held-out figures (markdown)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_lopo", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    a = ap.parse_args(argv)
    items = _load(a.data)
    grid = {}
    for rms, rho in itertools.product(MIN_RMS_GRID, PHASE_GRID):
        grid[(rms, rho)] = _counts(items, gyro_min_rms_rads=rms, gyro_phase_correlation=rho)
        print(f"grid {rms} {rho}: {_score(grid[(rms, rho)]):.4f}", file=sys.stderr)
    alone = _counts(items, use_gyroscope=False)
    print("Leave-one-person-out: settings chosen on the other two people, scored on the person left out\n")
    cols = ["left out", "chosen (rms, phase)", "training score", "held-out score", "held-out, accelerometer alone", *SCORED]
    print("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols))
    for held in PEOPLE:
        train = {k: _score(v[v["person"] != held]) for k, v in grid.items()}
        best = max(train, key=train.get)
        te = grid[best][grid[best]["person"] == held]
        te0 = alone[alone["person"] == held]
        per = te.groupby("motion")["acc"].mean()
        per0 = te0.groupby("motion")["acc"].mean()
        cells = [held, f"{best[0]}, {best[1]}", f"{train[best]:.4f}", f"{_score(te):.4f}", f"{_score(te0):.4f}"]
        cells += [f"{per[m]:.3f} ({per0[m]:.3f})" for m in SCORED]
        print("| " + " | ".join(cells) + " |")
    allp = {k: _score(v) for k, v in grid.items()}
    print("\nEvery pair on all three people (in sample), best first:\n")
    print("| gyro_min_rms_rads | gyro_phase_correlation | score | " + " | ".join(SCORED) + " |\n|" + "---|" * (3 + len(SCORED)))
    for k in sorted(allp, key=allp.get, reverse=True):
        per = grid[k].groupby("motion")["acc"].mean()
        print(f"| {k[0]} | {k[1]} | {allp[k]:.4f} | " + " | ".join(f"{per[m]:.3f}" for m in SCORED) + " |")
    per0 = alone.groupby("motion")["acc"].mean()
    print(f"| accelerometer alone | | {_score(alone):.4f} | " + " | ".join(f"{per0[m]:.3f}" for m in SCORED) + " |")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
