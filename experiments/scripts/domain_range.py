"""The domain check read through the 2 g accelerometer range, the classifier not (lab measurement, no fitting).

``python -m experiments.scripts.domain_range --data ../shared/data --base /tmp/runflag/folds --clip /tmp/runflag/folds-clip``
from the repository root.

``--base``: the fold models of the shipped recipe (``experiments.scripts.tyrex_modes --recipes a --model-cache``);
``--clip``: the same recipe trained with ``--acc-range-ms2 19.6`` (every training accelerometer clipped per axis at
+-2 g, the range of the Nexus 5 and iPhone 4S, a sensor fact). The *hybrid* reads each window's mode from the
base model (its classifier, still gate, corrections) and its ``in_domain`` from the clipped model, which computes
its domain check (feature distance, gravity, orientation dynamics) on the recording clipped at 2 g and its
foot-placement rule on the raw recording: exactly a domain record fitted, and read, through the range while the
classifier reads every phone as it comes. Scored as ``tyrex_modes`` scores (each tyrex person left out, the
speed rule; held-out simulator seed 2024; untrained positions), base against hybrid.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd


class Hybrid:
    """Modes of ``base``, ``in_domain`` (and its reason) of ``clip``."""

    def __init__(self, base, clip):
        self.base, self.clip = base, clip

    def __getattr__(self, k):
        return getattr(self.base, k)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--base", type=Path, required=True)
    ap.add_argument("--clip", type=Path, required=True)
    ap.add_argument("--csv", type=Path, default=None)
    a = ap.parse_args(argv)
    import gaitml.models as gm
    from experiments.scripts import tyrex_modes as tm
    from gaitml.pipeline.config import load_config

    plain = gm.predict_recording

    def predict(model, rec, **kw):
        if not isinstance(model, Hybrid):
            return plain(model, rec, **kw)
        p = plain(model.base, rec, **kw)
        q = plain(model.clip, rec, **kw)
        p["in_domain"] = q["in_domain"].to_numpy()
        p["out_of_domain_reason"] = q["out_of_domain_reason"].to_numpy()
        return p

    gm.predict_recording = predict
    cfg = tm.simulated_part(load_config(a.config))
    items = tm.load_tyrex_labelled(a.data, cfg["data"]["resample_hz"])
    positions = cfg["data"]["simulated"]["positions"]
    sim_test = tm._sim(cfg, tm.HELDOUT_SEED, 2, [*positions, "bag", "belt"])
    tabs, sides, untr = {"base": [], "hybrid": []}, {"base": [], "hybrid": []}, []
    for person in sorted({it["subject"] for it in items}):
        base = gm.load_model(a.base / f"a-{person}")
        clip = gm.load_model(a.clip / f"a-{person}")
        test = [it for it in items if it["subject"] == person]
        for name, model in (("base", base), ("hybrid", Hybrid(base, clip))):
            t = tm.window_table(model, test)
            t["arm"], t["left_out"] = name, person
            tabs[name].append(t)
            s = tm.sim_side_table(model, [r for r in sim_test if r.meta["position"] in positions])
            s["arm"], s["left_out"] = name, person
            sides[name].append(s)
            for row in tm.untrained_table(model, sim_test, a.data):
                untr.append({**row, "arm": name, "left_out": person})
        print(f"[domain_range] {person} left out done", file=sys.stderr)
    for name in ("base", "hybrid"):
        t = pd.concat(tabs[name], ignore_index=True)
        print(f"\n### {name}: each tyrex person left out (speed rule)\n")
        print(tm.md(tm.summarise(t, by="left_out")))
        per = t.groupby(["motion", "left_out"], sort=False)[["n", "right", "flagged", "wrong"]].sum()
        per = per.assign(right=per["right"] / per["n"], flagged=per["flagged"] / per["n"], wrong=per["wrong"] / per["n"]).reset_index()
        print(f"\n{name}: per motion and left-out person (right / flagged / silently wrong)\n")
        print(tm.md(per))
        s = pd.concat(sides[name], ignore_index=True)
        g = s.groupby(["position", "mode"], sort=False)[["n", "right", "flagged", "wrong"]].sum().reset_index()
        rng = s.assign(r=s["right"] / s["n"]).groupby(["position", "mode"], sort=False)["r"].agg(["min", "max"]).reset_index()
        g["right over folds"] = [f"{lo:.2f}-{hi:.2f}" for lo, hi in zip(rng["min"], rng["max"], strict=True)]
        for c in ("right", "flagged", "wrong"):
            g[c] = g[c] / g["n"]
        print(f"\n{name}: held-out simulator (seed {tm.HELDOUT_SEED}, summed over the folds' models)\n")
        print(tm.md(g))
    u = pd.DataFrame(untr)
    print("\nnot trained on, flagged (per fold model, left out: " + ", ".join(sorted(u["left_out"].unique())) + ")\n")
    print(
        tm.md(u.pivot_table(index="what", columns="arm", values="flagged", aggfunc=lambda v: "/".join(f"{x:.2f}" for x in v)).reset_index())
    )
    if a.csv:
        pd.concat([*tabs["base"], *tabs["hybrid"]], ignore_index=True).to_csv(a.csv, index=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
