"""Where `adaptive`'s count errors sit on the Oxford recordings, with and without its bout rules (issue 13).

``python -m experiments.scripts.step_bouts [--data DIR] [--positions NeckPouch ...] [--sensitivity] [--csv FILE]``

- Per recording (markdown): true steps, the detected count of ``adaptive``
  without its bout rules (``edge_confidence_ratio=0, min_bout_steps=1``: the
  counts before the rules), with them (the defaults) and of ``adfsm``; for each,
  the detected steps more than the matching tolerance before the first
  foot-switch step (``pre``) and after the last one (``post``), and the count
  error between them (``inside``).
- Per position: false and missed steps of ``adaptive`` (one-to-one matching
  at 0.25 s) without and with the rules.
- ``--sensitivity``: mean count accuracy per position (hard floor), carpet and
  the IFSM counts for ``edge_confidence_ratio`` 0-0.7 and ``min_bout_steps``
  1-8, around the defaults (0.5, 4), which were chosen by reasoning, not from
  this table.

Credit: "Oxford step counter data set, Salvi et al." (CC BY 4.0).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.evaluation.steps import evaluate_steps
from gaitml.pipeline.config import STEP_TOLERANCE_S
from gaitml.pipeline.steps_real import load_recordings
from gaitml.steps import get_detector

__all__ = ["edge_table", "sensitivity_table", "main"]

#: ``adaptive`` without its bout rules: the steps it counted before them
RULES_OFF = {"edge_confidence_ratio": 0.0, "min_bout_steps": 1}
VARIANTS = {"adaptive, no bout rules": ("adaptive", RULES_OFF), "adaptive": ("adaptive", {}), "adfsm": ("adfsm", {})}


def _md(df: pd.DataFrame) -> str:
    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(str(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def edge_table(recordings, positions=None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per-recording edge / inside errors of each variant, and false / missed steps per position."""
    rows, fpfn = [], []
    for rec in recordings:
        if rec.meta.get("format") != "oxford" or (positions and rec.meta["position"] not in positions):
            continue
        ts = np.asarray(rec.reference["steps_t_s"], dtype=float)
        t0, t1 = ts.min(), ts.max()
        row = {"recording": rec.name, "surface": rec.meta["surface"], "position": rec.meta["position"], "true": len(ts)}
        for label, (name, params) in VARIANTS.items():
            st = get_detector(name, **params).detect(rec).steps_
            t = st[st.attrs.get("event", "t_peak_s")].to_numpy()
            pre = int((t < t0 - STEP_TOLERANCE_S).sum())
            post = int((t > t1 + STEP_TOLERANCE_S).sum())
            row[label] = f"{len(t)} ({len(t) - len(ts):+d}): {pre} / {post} / {len(t) - pre - post - len(ts):+d}"
            if name != "adaptive":
                continue  # the FSMs time a step by its end: their matches at the tolerance are not comparable
            ev = evaluate_steps(st, ts, tolerance_s=STEP_TOLERANCE_S)
            fpfn.append(
                {
                    "variant": label,
                    "surface": rec.meta["surface"],
                    "position": rec.meta["position"],
                    "false": ev["n_detected"] - ev["n_matched"],
                    "missed": len(ts) - ev["n_matched"],
                }
            )
        rows.append(row)
    if not rows:
        raise InputError("no Oxford recording matched; check --data and --positions (e.g. NeckPouch, InHand).")
    per_pos = pd.DataFrame(fpfn).groupby(["surface", "position", "variant"], sort=False)[["false", "missed"]].sum().unstack("variant")
    per_pos.columns = [f"{v}: {k}" for k, v in per_pos.columns]
    return pd.DataFrame(rows), per_pos.reset_index()


def sensitivity_table(recordings) -> pd.DataFrame:
    """Mean count accuracy (%) per hard-floor position, carpet and IFSM counts over a grid of the two bout constants."""
    settings = [RULES_OFF] + [{"edge_confidence_ratio": r, "min_bout_steps": 4} for r in (0.0, 0.3, 0.4, 0.5, 0.6, 0.7)]
    settings += [{"edge_confidence_ratio": 0.5, "min_bout_steps": m} for m in (1, 2, 3, 5, 6, 8)]
    rows = []
    for p in settings:
        for rec in recordings:
            n = len(get_detector("adaptive", **p).detect(rec).steps_)
            ref = rec.reference
            nt = int(ref.get("n_steps_true") or len(ref["steps_t_s"]))
            ox = rec.meta.get("format") == "oxford"
            rows.append(
                {
                    "setting": f"ratio {p['edge_confidence_ratio']:g}, min bout {p['min_bout_steps']}",
                    "set": f"{rec.meta['surface']}" if ox else "IFSM",
                    "position": rec.meta["position"] if ox else rec.name,
                    "n": n,
                    "acc": 1 - abs(n - nt) / nt,
                }
            )
    df = pd.DataFrame(rows)
    t = df[df["set"] != "IFSM"].groupby(["setting", "set", "position"], sort=False)["acc"].mean().unstack("position") * 100
    out = t.xs("Hard", level="set").copy() if "Hard" in t.index.get_level_values("set") else pd.DataFrame(index=t.index.levels[0])
    out["ALL"] = out.mean(axis=1)
    out["worst"] = out.drop(columns="ALL").min(axis=1)
    if "Carpet" in t.index.get_level_values("set"):
        out["carpet"] = t.xs("Carpet", level="set").mean(axis=1)
    ifsm = df[df["set"] == "IFSM"]
    if len(ifsm):
        out["IFSM"] = ifsm.groupby("setting", sort=False)["n"].apply(lambda s: " / ".join(map(str, s)))
    return out.round(2).reset_index()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.step_bouts", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(Path(__file__).resolve().parents[3] / "shared" / "data"), help="shared data folder")
    ap.add_argument("--positions", nargs="*", help="only these positions (default: all)")
    ap.add_argument("--sensitivity", action="store_true", help="also the grid of the two bout constants")
    ap.add_argument("--csv", help="also write the per-recording table to this CSV")
    a = ap.parse_args(argv)
    recs = load_recordings(Path(a.data))
    if not recs:
        raise InputError(f"no step recordings under {a.data}; pass --data SHARED_DATA_DIR.")
    per_rec, per_pos = edge_table(recs, a.positions)
    print("cells: detected (error): pre / post / inside error\n")
    print(_md(per_rec) + "\n")
    print(_md(per_pos) + "\n")
    if a.csv:
        per_rec.to_csv(a.csv, index=False)
    if a.sensitivity:
        print(_md(sensitivity_table(recs)))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
