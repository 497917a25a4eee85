"""Step counts on the tyrex recordings taken down to lower sampling rates, against the motion-capture count.

``python -m experiments.scripts.tyrex_steps_rates --data ../shared/data [--rates native,50,20,15,10]
[--detectors adaptive,single-peak] [--csv FILE]`` from the repository root.

Each recording is taken down to each rate with :func:`gaitml.models.resample_recording` (a low-pass at 0.45 x the
new rate, then linear interpolation: what a phone logging at that rate delivers, up to its own filter), and each
detector counts its steps at its defaults over the motion-capture span; the reference is the motion-capture count
of :mod:`experiments.scripts.tyrex_steps`. Nothing is fitted. The table is the mean count accuracy
(1 - |n - n_ref| / n_ref) per motion, as in ``experiments/reports/tyrex-steps.md``.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pandas as pd


def count_table(data: str, rates: list[float | None], detectors: list[str]) -> pd.DataFrame:
    """One row per tyrex recording: motion, person, the motion-capture count and each detector's count at each rate."""
    from experiments.scripts.tyrex_steps import in_reference_span, truth_clock_s, tyrex_walks
    from gaitml.models import resample_recording
    from gaitml.steps import get_detector

    rows = []
    for walk in tyrex_walks(data):
        ref = walk["ref"]
        row = {"recording": walk["name"], "motion": walk["motion"], "person": walk["person"], "mocap_steps": ref["n_steps"]}
        for fs in rates:
            for d in detectors:
                n = 0
                for r in walk["recs"]:
                    rr = r if fs is None else resample_recording(r, fs)
                    st = get_detector(d).detect(rr).steps_
                    n += int(np.sum(in_reference_span(truth_clock_s(st, rr), ref)))
                row[f"{d} @ {'native' if fs is None else f'{fs:g} Hz'}"] = n
        rows.append(row)
        print(f"[tyrex_steps_rates] {walk['name']}", file=sys.stderr)
    return pd.DataFrame(rows)


def accuracy(df: pd.DataFrame) -> pd.DataFrame:
    """Mean count accuracy per motion of every count column (``detector @ rate``)."""
    cols = [c for c in df.columns if " @ " in c]
    out = {}
    for motion, g in df.groupby("motion"):
        ref = g["mocap_steps"].clip(lower=1)
        out[motion] = {c: float((1 - (g[c] - g["mocap_steps"]).abs() / ref).mean()) for c in cols}
    return pd.DataFrame(out).T


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--rates", default="native,50,20,15,10", help="comma-separated: 'native' and/or rates in Hz")
    ap.add_argument("--detectors", default="adaptive,single-peak")
    ap.add_argument("--csv", default=None, help="per-recording counts")
    a = ap.parse_args(argv)
    rates = [None if r == "native" else float(r) for r in a.rates.split(",") if r]
    df = count_table(a.data, rates, [d for d in a.detectors.split(",") if d])
    if a.csv:
        df.to_csv(a.csv, index=False)
    acc = accuracy(df)
    cols = list(acc.columns)
    print("| motion | " + " | ".join(cols) + " |")
    print("|---|" + "---|" * len(cols))
    for motion, r in acc.iterrows():
        print(f"| {motion} | " + " | ".join(f"{r[c]:.3f}" for c in cols) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
