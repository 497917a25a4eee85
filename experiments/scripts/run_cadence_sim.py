"""Do the simulated runs come at a running cadence? The run-cadence rule's window cadence on labelled simulator windows.

``python -m experiments.scripts.run_cadence_sim [--config experiments/demo.toml] [--seed 2024] [--subjects 2]`` from the
repository root. No classifier: every window of the simulated recordings (the config's simulated positions, its
modes) gets :func:`gaitml.models._predict.window_step_cadence`; per position and true mode, the share of windows at a
running cadence (>= :data:`~gaitml.models._predict.RUN_MIN_CADENCE_HZ`), in the rule's walking band
(:data:`~gaitml.models._predict.RUN_STRIDE_CADENCE_HZ` to it), under the band, and without a step near them.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import _sim, md, simulated_part
    from gaitml.models._predict import RUN_MIN_CADENCE_HZ, RUN_STRIDE_CADENCE_HZ, _windows_for, window_step_cadence
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--subjects", type=int, default=2)
    a = ap.parse_args(argv)
    cfg = simulated_part(load_config(a.config))
    w_cfg = cfg["windows"]
    rows = []
    for r in _sim(cfg, a.seed, a.subjects, cfg["data"]["simulated"]["positions"]):
        w = _windows_for(r, w_cfg["length_s"], w_cfg["overlap"])
        c = window_step_cadence(r, w)
        lab = w["label"].astype(str).to_numpy()
        keep = w["label_fraction"].to_numpy() >= 0.5
        for m in np.unique(lab[keep]):
            s = keep & (lab == m)
            rows.append(
                {
                    "position": r.meta["position"],
                    "mode": m,
                    "n": int(s.sum()),
                    "running": int(np.sum(s & (c >= RUN_MIN_CADENCE_HZ))),
                    "walking band": int(np.sum(s & (c >= RUN_STRIDE_CADENCE_HZ) & (c < RUN_MIN_CADENCE_HZ))),
                    "under": int(np.sum(s & (c < RUN_STRIDE_CADENCE_HZ))),
                    "no step": int(np.sum(s & np.isnan(c))),
                }
            )
    t = pd.DataFrame(rows).groupby(["position", "mode"], sort=False).sum().reset_index()
    for k in ("running", "walking band", "under", "no step"):
        t[k] = t[k] / t["n"]
    print(f"seed {a.seed}, {a.subjects} subjects: share of windows by their window cadence\n")
    print(md(t))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
