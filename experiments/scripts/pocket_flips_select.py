"""Choosing ``data.augment.flips`` (pocket flips) on the training people only (nested person-out folds on tyrex).

``python -m experiments.scripts.pocket_flips_select --data ../shared/data [--variants none,y,x+y+z] [--cache /tmp/pocket]``
from the repository root.

For every ordered pair of tyrex people (train on R, score Q) recipe a of ``experiments/demo.toml``
(its ``[data.augment]`` swing turns as shipped) is trained on R's real moving windows plus the
pocket flips of the variant (:func:`gaitml.pipeline.augment.flip_rotation`; ``+`` joins the axes
of one variant; ``--flip-positions``, default the pockets) and the simulated part, and scored on
Q through :func:`gaitml.models.predict_recording` (right / flagged / silently wrong per motion).
The outer fold that leaves out person P may only use the pairs among the two other people: the
table prints, per outer fold, the mean over its two inner pairs, and the variant each outer fold
chooses: the largest right share over the windows of the flipped positions' motions (the
criterion, ``--criterion``, fixed before any run), ties within 0.005 to fewer flips. Rows are
cached per pair and variant under ``CACHE/select``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

#: tyrex motions whose recordings carry each flip position (meta ``position``)
POSITION_MOTIONS = {"front-pocket": "FrontPocket", "back-pocket": "BackPocket", "pocket": "RunningPocket", "swinging-hand": "Swinging"}


def main(argv=None) -> int:
    from experiments.scripts.tyrex_folds import load_items
    from experiments.scripts.tyrex_modes import MOTION_ORDER, _sim, augment_of, md, simulated_part, train_recipe, window_table
    from gaitml.pipeline.augment import POCKET_POSITIONS
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--variants", default="none,y,x+y+z")
    ap.add_argument("--flip-positions", default=",".join(POCKET_POSITIONS))
    ap.add_argument(
        "--criterion", default=None, help="comma-separated motions whose pooled right share chooses (default: the flipped positions')"
    )
    ap.add_argument("--cache", type=Path, default=Path("/tmp/pocket"))
    a = ap.parse_args(argv)
    full = load_config(a.config)
    turns, turn_positions, share_time = augment_of(full)
    cfg = simulated_part(full)
    out = a.cache / "select"
    out.mkdir(parents=True, exist_ok=True)
    items = load_items(a.data, cfg["data"]["resample_hz"], a.cache)
    people = sorted({it["subject"] for it in items})
    fpos = a.flip_positions.split(",")
    crit = a.criterion.split(",") if a.criterion else [POSITION_MOTIONS[p] for p in fpos if p in POSITION_MOTIONS]
    variants = a.variants.split(",")
    sim = None
    rows = []
    for v in variants:
        flips = [] if v == "none" else v.split("+")
        for r in people:
            for q in people:
                if q == r:
                    continue
                f = out / f"{v}-{'+'.join(fpos)}-t{turns}{'s' if share_time else ''}-{r}-{q}.pkl"
                if not f.exists():
                    t0 = time.perf_counter()
                    if sim is None:
                        sim = _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
                    with tempfile.TemporaryDirectory() as tmp:
                        model, _ = train_recipe(
                            cfg,
                            sim,
                            [it for it in items if it["subject"] == r],
                            "a",
                            Path(tmp) / "m",
                            augment=turns,
                            augment_positions=turn_positions,
                            share_time=share_time,
                            flips=flips,
                            flip_positions=fpos,
                        )
                    window_table(model, [it for it in items if it["subject"] == q]).to_pickle(f)
                    print(f"[pocket_flips_select] flips {v}: train {r}, score {q} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
                rows.append(pd.read_pickle(f).assign(variant=v, n_flips=len(flips), trained_on=r, scored=q))
    t = pd.concat(rows, ignore_index=True)
    g = t.groupby(["variant", "n_flips", "trained_on", "scored", "motion"])[["n", "right", "flagged", "wrong"]].sum().reset_index()
    g["r"] = g["right"] / g["n"]
    c = t[t["motion"].isin(crit)].groupby(["variant", "n_flips", "trained_on", "scored"])[["n", "right"]].sum().reset_index()
    c["r"] = c["right"] / c["n"]
    lines = [f"criterion: right over the windows of {', '.join(crit)} (pooled per pair, mean over the inner pairs)"]
    for p in people:  # outer fold leaving out p: the pairs among the others
        inner = g[(g["trained_on"] != p) & (g["scored"] != p)]
        tab = inner.groupby(["variant", "motion"])["r"].mean().unstack("motion")[list(MOTION_ORDER)].reindex(variants)
        ci = c[(c["trained_on"] != p) & (c["scored"] != p)].groupby(["variant", "n_flips"])["r"].mean().reset_index()
        tab["criterion"] = ci.set_index("variant")["r"].reindex(variants)
        best = ci["r"].max()
        chosen = ci[ci["r"] >= best - 0.005].sort_values("n_flips").iloc[0]["variant"]
        lines.append(f"\n### outer fold: {p} left out (inner pairs among the other two; mean right over the two pairs)\n")
        lines.append(md(tab.reset_index()))
        lines.append(f"\nchosen: flips = {chosen}")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
