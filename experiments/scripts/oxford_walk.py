"""Real Oxford walking as ``walk`` training windows for the accelerometer-only default model, scored held out.

``python -m experiments.scripts.oxford_walk [--data ../shared/data] [--config experiments/demo-acc.toml]
[--out FILE]`` from the repository root.

The shipped recipe (``experiments/demo-acc.toml``: the real tyrex walks and runs of the people
trained on, plus its simulated subjects) with the Oxford step-counter walks added as ``walk``:
only the samples inside a stretch of foot-switch steps (:func:`gaitml.pipeline.runner.step_walking_labels`, the rule of a config's ``[data.walks]``) are labelled ``walk``; the rest of a
recording (standing at its start and end) is ``unlabelled`` and gives no training window.

Two sets of folds, every window through :func:`gaitml.models.predict_recording` (the path of
``gaitml predict``):

- each Oxford user left out (trained on every tyrex person and the two other Oxford users): the
  left-out user's walks per carrying position, every window scored walk / still / flagged /
  silently wrong (as ``experiments.scripts.default_model``);
- each tyrex person left out (trained on the two other tyrex people and every Oxford user): the
  left-out person's moving windows per motion (as ``experiments.scripts.tyrex_modes``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.pipeline.runner import WALK_MAX_STEP_GAP_S as MAX_STEP_GAP_S  # noqa: F401 (the study's rule is the pipeline's)
from gaitml.pipeline.runner import WALK_STEP_PAD_S as STEP_PAD_S  # noqa: F401
from gaitml.pipeline.runner import step_walking_labels as walking_labels


def load_oxford_walks(data: Path, fs: float) -> list[dict]:
    from gaitml.io import read_dataset
    from gaitml.models import resample_recording

    out = []
    for r in read_dataset(data / "oxford-step-counter" / "optimisation"):
        rec = resample_recording(r, fs)
        lab = walking_labels(rec)
        rec = rec.replace(labels=lab, meta={**rec.meta, "subject": f"oxford-{r.meta['user']}"}, check_units=False)
        out.append({"recording": rec, "subject": f"oxford-{r.meta['user']}", "user": r.meta["user"], "position": r.meta["position"]})
    return out


def main(argv=None) -> int:
    from experiments.scripts.default_model import OXFORD_POSITIONS, md, score_walk
    from experiments.scripts.tyrex_modes import _sim, load_tyrex_labelled, simulated_part, summarise, train_recipe, window_table
    from gaitml.models import load_model
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo-acc.toml"))
    ap.add_argument("--baseline", default="models/demo-acc", help="a shipped model scored on the same Oxford walks ('' = none)")
    ap.add_argument("--folds", default="oxford,tyrex")
    ap.add_argument("--oxford-weight", type=int, default=1, help="each Oxford walking window counts this many times in training")
    ap.add_argument(
        "--nested",
        default="",
        help="comma-separated Oxford weights: choose the weight per left-out user on the two other users alone "
        "(inner leave-one-user-out, lowest pocket silently-wrong share, ties to the smaller weight)",
    )
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    cfg = simulated_part(load_config(a.config))
    fs = float(cfg["data"]["resample_hz"])
    t0 = time.perf_counter()
    tyrex = load_tyrex_labelled(a.data, fs)
    oxford = load_oxford_walks(a.data, fs)
    n_walk = sum(int(np.sum(it["recording"].labels == "walk")) for it in oxford)
    n_all = sum(it["recording"].n_samples for it in oxford)
    print(f"[oxford_walk] {len(tyrex)} tyrex, {len(oxford)} Oxford recordings ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    sim = _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
    text: list[str] = []

    def emit(s=""):
        print(s, flush=True)
        text.append(s)

    emit(f"Oxford samples labelled walk (inside a stretch of foot-switch steps): {n_walk / n_all:.3f} of {n_all}")
    users = sorted({it["user"] for it in oxford})

    def oxford_rows(model, name, items, left_out):
        rows = []
        for pos in OXFORD_POSITIONS:
            its = [it["recording"] for it in items if it["position"].lower() == pos.lower()]
            if its:
                c = score_walk(model, its)
                n = max(c["windows"], 1)
                rows.append(
                    {
                        "model": name,
                        "left out": left_out,
                        "position": pos,
                        "windows": c["windows"],
                        **{k: c[k] / n for k in ("walk", "still", "flagged", "silently wrong")},
                    }
                )
        return rows

    if "oxford" in a.folds:
        rows = []
        for mdir in [m for m in a.baseline.split(",") if m]:
            for u in users:
                rows += oxford_rows(load_model(mdir), mdir, [it for it in oxford if it["user"] == u], u)
        weights = [int(w) for w in a.nested.split(",") if w]
        for u in users:
            t1 = time.perf_counter()
            w_u, label = a.oxford_weight, f"+ Oxford walk x{a.oxford_weight}"
            if weights:
                inner = {}
                for w in weights:
                    n = k = 0
                    for v in [x for x in users if x != u]:
                        tr = tyrex + [it for it in oxford if it["user"] not in (u, v)] * w
                        with tempfile.TemporaryDirectory() as tmp:
                            m_in, _ = train_recipe(cfg, sim, tr, "a", Path(tmp) / "m")
                        c = score_walk(m_in, [it["recording"] for it in oxford if it["user"] == v and "pocket" in it["position"].lower()])
                        n += c["windows"]
                        k += c["silently wrong"]
                    inner[w] = k / max(n, 1)
                w_u = min(weights, key=lambda w: (round(inner[w], 3), w))
                label = "+ Oxford walk, weight chosen within the fold"
                emit(f"{u} out: inner pocket silently wrong per weight {', '.join(f'x{w} {x:.3f}' for w, x in inner.items())} -> x{w_u}")
            train = tyrex + [it for it in oxford if it["user"] != u] * w_u
            with tempfile.TemporaryDirectory() as tmp:
                model, n_win = train_recipe(cfg, sim, train, "a", Path(tmp) / "m")
            rows += oxford_rows(model, label, [it for it in oxford if it["user"] == u], u)
            print(f"[oxford_walk] Oxford {u} out: {n_win} windows, {time.perf_counter() - t1:.0f} s", file=sys.stderr)
        df = pd.DataFrame(rows)
        emit("\n### Each Oxford user left out: every window of their walks\n")
        emit(md(df))
        emit("\n### Pooled over the left-out users\n")
        pooled = []
        for (m, pos), g in df.groupby(["model", "position"], sort=False):
            n = g["windows"].sum()
            pooled.append(
                {
                    "model": m,
                    "position": pos,
                    "windows": int(n),
                    **{k: float((g[k] * g["windows"]).sum() / n) for k in ("walk", "still", "flagged", "silently wrong")},
                    "silently wrong per user": f"{g['silently wrong'].min():.2f}-{g['silently wrong'].max():.2f}",
                }
            )
        emit(md(pd.DataFrame(pooled)))
    if "tyrex" in a.folds:
        tabs = []
        for p in sorted({it["subject"] for it in tyrex}):
            t1 = time.perf_counter()
            train = [it for it in tyrex if it["subject"] != p] + oxford * a.oxford_weight
            with tempfile.TemporaryDirectory() as tmp:
                model, n_win = train_recipe(cfg, sim, train, "a", Path(tmp) / "m")
            t = window_table(model, [it for it in tyrex if it["subject"] == p])
            t["left_out"] = p
            tabs.append(t)
            print(f"[oxford_walk] tyrex {p} out: {n_win} windows, {time.perf_counter() - t1:.0f} s", file=sys.stderr)
        t = pd.concat(tabs)
        emit("\n### Each tyrex person left out (trained with every Oxford user's walks)\n")
        emit(md(summarise(t)))
        per = t.groupby(["motion", "left_out"])[["right", "flagged", "wrong", "n"]].sum()
        emit("\nper left-out person (right / flagged / silently wrong):\n")
        emit(
            md(
                pd.DataFrame(
                    [
                        {
                            "motion": m,
                            "left out": p,
                            "right": r["right"] / r["n"],
                            "flagged": r["flagged"] / r["n"],
                            "silently wrong": r["wrong"] / r["n"],
                        }
                        for (m, p), r in per.iterrows()
                    ]
                )
            )
        )
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
