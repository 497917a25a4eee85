"""Choosing ``data.augment.swing_turns`` on the training people only (nested person-out folds on tyrex).

``python -m experiments.scripts.swing_turns_select --data ../shared/data [--turns 0,1,3,7] [--share-time] [--cache /tmp/runswing]``
from the repository root.

For every ordered pair of tyrex people (train on R, score Q) recipe a of
``experiments/demo.toml`` is trained on R's real moving windows (plus their rotated copies,
:mod:`gaitml.pipeline.augment`) and the simulated part, and scored on Q through
:func:`gaitml.models.predict_recording` (right / flagged / silently wrong per motion). The
outer fold that leaves out person P may only use the pairs among the two other people: the
table prints, per outer fold, the mean over its two inner pairs, and the value each outer
fold would choose (largest Swinging right, ties to fewer copies). Rows are cached per
pair and value under ``CACHE/select``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd


def main(argv=None) -> int:
    from experiments.scripts.tyrex_folds import load_items
    from experiments.scripts.tyrex_modes import MOTION_ORDER, _sim, md, simulated_part, train_recipe, window_table
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--turns", default="0,1,3,7")
    ap.add_argument("--positions", default="swinging-hand")
    ap.add_argument("--cache", type=Path, default=Path("/tmp/runswing"))
    ap.add_argument("--share-time", action="store_true", help="the original and its copies share the recording's time")
    a = ap.parse_args(argv)
    cfg = simulated_part(load_config(a.config))
    out = a.cache / "select"
    out.mkdir(parents=True, exist_ok=True)
    items = load_items(a.data, cfg["data"]["resample_hz"], a.cache)
    people = sorted({it["subject"] for it in items})
    sim = None
    rows = []
    for n in [int(x) for x in a.turns.split(",")]:
        for r in people:
            for q in people:
                if q == r:
                    continue
                f = out / f"{n}-{a.positions}{'-shared' if a.share_time else ''}-{r}-{q}.pkl"
                if not f.exists():
                    t0 = time.perf_counter()
                    sim = (
                        sim
                        if sim is not None
                        else _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
                    )
                    with tempfile.TemporaryDirectory() as tmp:
                        model, _ = train_recipe(
                            cfg,
                            sim,
                            [it for it in items if it["subject"] == r],
                            "a",
                            Path(tmp) / "m",
                            augment=n,
                            augment_positions=a.positions.split(","),
                            share_time=a.share_time,
                        )
                    window_table(model, [it for it in items if it["subject"] == q]).to_pickle(f)
                    print(f"[swing_turns_select] turns {n}: train {r}, score {q} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
                t = pd.read_pickle(f).assign(turns=n, trained_on=r, scored=q)
                rows.append(t)
    t = pd.concat(rows, ignore_index=True)
    g = t.groupby(["turns", "trained_on", "scored", "motion"])[["n", "right", "flagged", "wrong"]].sum().reset_index()
    g["r"] = g["right"] / g["n"]
    lines = []
    for p in people:  # outer fold leaving out p: the pairs among the others
        inner = g[(g["trained_on"] != p) & (g["scored"] != p)]
        tab = inner.groupby(["turns", "motion"])["r"].mean().unstack("motion")[list(MOTION_ORDER)]
        best = tab["Swinging"].round(3).idxmax()
        lines.append(f"\n### outer fold: {p} left out (inner pairs among the other two; mean right over the two pairs)\n")
        lines.append(md(tab.reset_index()))
        lines.append(f"\nchosen: swing_turns = {best}")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
