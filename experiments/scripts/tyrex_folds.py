"""Cached person-out fold models of a tyrex recipe, and their per-window predictions (diagnosis of misread windows).

``python -m experiments.scripts.tyrex_folds --config experiments/demo.toml [--recipe a] [--cache /tmp/runswing] [--tag NAME]``
from the repository root.

Trains :func:`experiments.scripts.tyrex_modes.train_recipe` once per left-out tyrex person
(the same folds and settings as ``tyrex_modes --recipes a``) and keeps the models under
``CACHE/TAG/fold-PERSON``; then writes every left-out window's prediction
(:func:`gaitml.models.predict_recording`) with the domain columns and which test flagged it
(feature distance, gravity angle, dynamics span) to ``CACHE/TAG/windows.pkl``. A rerun
reuses the cached models.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd


def load_items(data: Path, fs: float, cache: Path) -> list[dict]:
    """:func:`tyrex_modes.load_tyrex_labelled`, pickled under ``cache``."""
    from experiments.scripts.tyrex_modes import load_tyrex_labelled

    f = cache / f"items-{fs:g}.pkl"
    if f.exists():
        return pickle.loads(f.read_bytes())
    items = load_tyrex_labelled(data, fs)
    f.write_bytes(pickle.dumps(items))
    return items


def fold_predictions(model, items: list[dict]) -> pd.DataFrame:
    """Per window of ``items``: prediction, label, domain columns, and which domain test failed."""
    from gaitml.models import predict_recording

    dom = model.domain
    rows = []
    for it in items:
        p = predict_recording(model, it["recording"])
        p = p.assign(subject=it["subject"], phone=it["phone"], motion=it["motion"], true_mode=it["mode"], recording=str(it.get("file", "")))
        p["fail_distance"] = p["domain_distance"] > dom.distance_threshold
        p["fail_gravity"] = (p["gravity_angle_deg"] > np.degrees(dom.gravity_threshold_rad)) if dom.gravity_check else False
        if "dynamics_distance" in p:
            p["fail_dynamics"] = p["dynamics_distance"] > dom.dynamics["threshold"]
        rows.append(p)
    return pd.concat(rows, ignore_index=True)


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import _sim, simulated_part, train_recipe
    from gaitml.models import load_model
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--cache", type=Path, default=Path("/tmp/runswing"))
    ap.add_argument("--tag", default="base")
    ap.add_argument("--augment", type=int, default=0, help="rotated copies per real recording (the phone turned about its swing axis)")
    ap.add_argument("--augment-positions", default=None, help="comma-separated positions to augment (default: the swinging ones)")
    ap.add_argument("--share-time", action="store_true", help="the original and its copies share the recording's time")
    a = ap.parse_args(argv)
    cfg = simulated_part(load_config(a.config))
    out = a.cache / a.tag
    out.mkdir(parents=True, exist_ok=True)
    items = load_items(a.data, cfg["data"]["resample_hz"], a.cache)
    sim_train = None
    tabs = []
    for person in sorted({it["subject"] for it in items}):
        t0 = time.perf_counter()
        mdir = out / f"fold-{person}"
        if not (mdir / "model.json").exists():
            if sim_train is None:
                sim_train = _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
            train_recipe(
                cfg,
                sim_train,
                [it for it in items if it["subject"] != person],
                a.recipe,
                mdir,
                augment=a.augment,
                augment_positions=a.augment_positions.split(",") if a.augment_positions else None,
                share_time=a.share_time,
            )
        model = load_model(mdir)
        tabs.append(fold_predictions(model, [it for it in items if it["subject"] == person]).assign(left_out=person))
        print(f"[tyrex_folds] {a.tag}: {person} out, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    t = pd.concat(tabs, ignore_index=True)
    t.to_pickle(out / "windows.pkl")
    print(f"[tyrex_folds] wrote {out / 'windows.pkl'} ({len(t)} windows)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
