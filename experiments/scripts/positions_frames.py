"""Per carrying position tables from run folders of simulated-position configs (issue 12).

``python -m experiments.scripts.positions_frames RUN_DIR ...`` reads the run folders
written by ``gaitml evaluate`` for configs with ``data.simulated.positions`` (e.g.
``experiments/positions-frames.toml``, ``positions-frames-mlp.toml``,
``positions-recognition.toml``) and prints markdown tables. One column per run and
sweep point (model kind x ``features.frame``). Scores use the headline predictions:
after the adjacent-window correction (paper 003 sec. 3.4) when the config applies it,
else before.

The position of a window comes from its recording's name, which the simulator makes
``S<subject>-R<session>-<position>`` (:func:`gaitml.simulate.simulate_dataset`).

Tables (``--task modes``, the default):

- per position: accuracy and macro-F1 over that position's test windows (all modes);
- per mode: F1 of the mode pooled over every position; ``all``: pooled accuracy / macro-F1;
- per position and mode: recall (the fraction of that position's windows of that mode
  recognised).

``--task position`` (the carrying position is the label; any run folder, e.g. the real
``oxford-position-gravity.toml`` runs): pooled accuracy / macro-F1 and the per-position F1
and recall.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = ["read_points", "mode_tables", "position_tables", "position_of"]

_NAME = re.compile(r"^S\d+-R\d+-(?P<position>.+)$")
_MODEL = {"linear-ovo-svm": "SVM", "mlp": "MLP", "cnn1d": "CNN"}


def position_of(recording: str) -> str:
    """The carrying position in a simulated recording name ``S01-R1-front-pocket``."""
    m = _NAME.match(str(recording))
    if m is None:
        raise InputError(f"recording {recording!r} is not named S<n>-R<n>-<position>; pass runs of configs with data.simulated.positions.")
    return m["position"]


def read_points(run_dirs, *, positions: bool = True) -> list[tuple[str, pd.DataFrame]]:
    """``(column name, predictions)`` of every run and sweep point, ``pred`` set to the headline prediction.

    With ``positions`` each window also gets its simulated recording's ``position``
    (InputError for a recording not named by the simulator); without it any run folder
    is read (e.g. the real Oxford position runs, whose label is the position).
    """
    out = []
    for d in map(Path, run_dirs):
        p = d / "metrics.json"
        if not p.is_file():
            raise InputError(f"{p} not found; pass run folders written by 'gaitml evaluate'.")
        m = json.loads(p.read_text())
        cfg = json.loads((d / "config.resolved.json").read_text())
        subs = sorted(d.glob("point-*")) or [d]
        for sub in subs:
            point = json.loads((sub / "metrics.json").read_text()).get("point", {}) if sub != d else {}
            kind = point.get("model.kind", m["model_kind"])
            frame = point.get("features.frame", cfg["features"]["frame"])
            extra = ", ".join(f"{k}={v}" for k, v in point.items() if k not in ("model.kind", "features.frame"))
            name = f"{_MODEL.get(kind, kind)} {frame}" + (f" ({extra})" if extra else "")
            pred = pd.read_csv(sub / "predictions.csv", keep_default_na=False)
            col = "pred_corrected" if m["correction_applied"] else "pred"
            df = pd.DataFrame({"label": pred["label"].astype(str), "pred": pred[col].astype(str)})
            if positions:
                df["position"] = [position_of(r) for r in pred["recording"]]
            out.append((name, df))
    return out


def _f1(y, p, labels) -> dict:
    out = {}
    for c in labels:
        tp = np.sum((y == c) & (p == c))
        n_true, n_pred = np.sum(y == c), np.sum(p == c)
        prec = tp / n_pred if n_pred else 0.0
        rec = tp / n_true if n_true else 0.0
        out[c] = {"precision": prec, "recall": rec, "f1": 2 * prec * rec / (prec + rec) if prec + rec else 0.0, "support": int(n_true)}
    return out


def _acc_f1(df: pd.DataFrame) -> tuple[float, float]:
    y, p = df["label"].to_numpy(), df["pred"].to_numpy()
    labels = sorted(set(y))
    per = _f1(y, p, labels)
    return float(np.mean(y == p)), float(np.mean([per[c]["f1"] for c in labels]))


def mode_tables(points) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(positions and modes: accuracy / F1 per column, position x mode recall per column)."""
    positions = list(dict.fromkeys(points[0][1]["position"]))
    modes = list(dict.fromkeys(points[0][1]["label"]))
    rows = []
    for pos in positions:
        row = {"row": f"position {pos}", "score": "accuracy / macro-F1"}
        for name, df in points:
            a, f = _acc_f1(df[df["position"] == pos])
            row[name] = f"{a:.3f} / {f:.3f}"
        rows.append(row)
    for mode in modes:
        row = {"row": f"mode {mode}", "score": "F1 (all positions)"}
        for name, df in points:
            row[name] = f"{_f1(df['label'].to_numpy(), df['pred'].to_numpy(), [mode])[mode]['f1']:.3f}"
        rows.append(row)
    row = {"row": "all", "score": "accuracy / macro-F1"}
    for name, df in points:
        a, f = _acc_f1(df)
        row[name] = f"{a:.3f} / {f:.3f}"
    rows.append(row)
    cells = []
    for pos in positions:
        for mode in modes:
            row = {"position": pos, "mode": mode}
            for name, df in points:
                sel = df[(df["position"] == pos) & (df["label"] == mode)]
                row[name] = f"{np.mean(sel['pred'] == mode):.3f}" if len(sel) else "-"
            cells.append(row)
    return pd.DataFrame(rows), pd.DataFrame(cells)


def position_tables(points) -> pd.DataFrame:
    """Position recognition: pooled accuracy / macro-F1 and per-position F1 per column."""
    labels = sorted(set(points[0][1]["label"]))
    rows = [{"row": "all", "score": "accuracy / macro-F1"}]
    for name, df in points:
        a, f = _acc_f1(df)
        rows[0][name] = f"{a:.3f} / {f:.3f}"
    for c in labels:
        row = {"row": c, "score": "F1 (recall)"}
        for name, df in points:
            s = _f1(df["label"].to_numpy(), df["pred"].to_numpy(), [c])[c]
            row[name] = f"{s['f1']:.3f} ({s['recall']:.3f})"
        rows.append(row)
    return pd.DataFrame(rows)


def _md(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(str(r[c]) for c in cols) + " |" for _, r in df.iterrows()]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.positions_frames", description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--task", choices=("modes", "position"), default="modes")
    args = ap.parse_args(argv)
    try:
        points = read_points(args.runs, positions=args.task == "modes")
    except InputError as exc:
        print(f"positions_frames: error: {exc}", file=sys.stderr)
        return 2
    if args.task == "modes":
        summary, cells = mode_tables(points)
        print(_md(summary) + "\n\nRecall per position and mode:\n\n" + _md(cells))
    else:
        print(_md(position_tables(points)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
