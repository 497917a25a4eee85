"""Review checks of the debt, backward and demo-retrain merges (branch review5; experiments/reports/review5.md).

Every figure of the report's "checked" tables, from the library as it is:

- ``veto``: ``gaitml pdr --model models/demo`` (:func:`gaitml.pdr.run_pdr`, ``modes='model'``) lean (the still gate's
  step-veto finder only where :func:`gaitml.models._predict.veto_can_change_step_modes` says it can change a step's
  mode) against forced-full (the predicate replaced by True): trajectory and step tables, on simulated walks with
  pauses, all five modes (side steps, run, backward) and the carrying positions, and on the tyrex recordings with
  motion capture (``--tyrex``).
- ``chunks``: ``gaitml predict`` whole (:func:`gaitml.models.predict_recording`) against chunked
  (:func:`gaitml.chunked_run.long_predict`, 37 s chunks) on simulated hand-held walks with pauses written at
  20, 50 and 100 Hz (20 and 100 Hz are resampled to the model's 50 Hz): windows whose columns differ.

    PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data python -m experiments.scripts.review5_checks [--tyrex]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

#: Simulated carrying positions of the veto check (gaitml.simulate's names).
POSITIONS = ("hand-flat", "hand-tilted", "swinging-hand", "front-pocket", "back-pocket", "belt")


def lean_vs_full(model, rec) -> dict:
    """One recording through run_pdr lean and forced-full: whether the predicate ran the finder, and what differs."""
    import gaitml.models._predict as P
    from gaitml.pdr import run_pdr

    real = P.veto_can_change_step_modes
    asked = []
    try:
        P.veto_can_change_step_modes = lambda s, m, r: asked.append(real(s, m, r)) or asked[-1]
        lean = run_pdr(rec, model=model, modes="model")
        P.veto_can_change_step_modes = lambda s, m, r: True
        full = run_pdr(rec, model=model, modes="model")
    finally:
        P.veto_can_change_step_modes = real
    differ = [c for c in lean.steps.columns if not lean.steps[c].astype(str).equals(full.steps[c].astype(str))]
    return {
        "recording": rec.name,
        "finder (lean)": "no still window" if not asked else ("ran" if asked[0] else "skipped"),
        "trajectory equal": bool(lean.trajectory.equals(full.trajectory)),
        "step columns differing": ", ".join(differ) or "-",
    }


def veto_rows(model, tyrex: bool) -> list[dict]:
    from gaitml.simulate import simulate_dataset

    rows = []
    for i, pos in enumerate(POSITIONS):
        for rec in simulate_dataset(n_subjects=2, duration_s=90.0, seed=31 + i, pauses=True, positions=pos):
            rows.append({"source": f"simulated {pos}", **lean_vs_full(model, rec)})
    if tyrex:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from tyrex_pdr import load_tyrex

        for item in load_tyrex(Path(os.environ.get("GAITML_SHARED_DATA", "../shared/data"))):
            rows.append({"source": "tyrex", **lean_vs_full(model, item["recording"])})
    return rows


def chunk_rows(model) -> list[dict]:
    from gaitml.chunked_run import long_predict
    from gaitml.io.gaitml_csv import read_gaitml_csv, write_gaitml_csv
    from gaitml.models import predict_recording
    from gaitml.simulate import simulate_dataset

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for fs, pos, seed in ((20.0, "hand-flat", 5), (20.0, "hand-tilted", 6), (50.0, "hand-flat", 7), (100.0, "hand-flat", 8)):
            path = Path(tmp) / f"sim_{int(fs)}_{pos}.csv"
            write_gaitml_csv(
                simulate_dataset(n_subjects=1, duration_s=240.0, seed=seed, pauses=True, positions=pos, sampling_rate_hz=fs)[0], path
            )
            whole = predict_recording(model, read_gaitml_csv(path))
            chunked = long_predict(model, path, chunk_s=37.0, progress=False)
            row = {"rate (Hz)": fs, "position": pos, "windows whole / chunked": f"{len(whole)} / {len(chunked)}"}
            for c in ("mode_raw", "mode", "still", "in_domain", "side_direction_unsure"):
                row[c] = int((whole[c].astype(str).to_numpy() != chunked[c].astype(str).to_numpy()).sum())
            rows.append(row)
    return rows


def main(argv=None) -> int:
    import pandas as pd

    from gaitml.models import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tyrex", action="store_true", help="also the tyrex recordings with motion capture (GAITML_SHARED_DATA)")
    a = ap.parse_args(argv)
    model = load_model(Path(__file__).resolve().parents[2] / "models" / "demo")
    veto = pd.DataFrame(veto_rows(model, a.tyrex))
    print("## veto finder: lean against forced-full\n")
    print(
        veto.groupby(["source", "finder (lean)"]).agg(n=("recording", "size"), trajectories_equal=("trajectory equal", "sum")).to_string()
    )
    print("recordings with a differing step column:", int((veto["step columns differing"] != "-").sum()), "of", len(veto))
    print("\n## predict whole against 37 s chunks (windows that differ)\n")
    print(pd.DataFrame(chunk_rows(model)).to_string(index=False))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
