"""One table from several run folders (``python -m experiments.scripts.compare_runs RUN_DIR ...``).

Each run's ``metrics.json`` gives one row, or one row per sweep point: name,
model kind, feature set, window length, scheme, accuracy and macro-F1 before and
after the adjacent-window correction. Printed as markdown; ``--csv FILE`` also
writes it.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pandas as pd

from gaitml.errors import InputError

__all__ = ["compare_runs"]


def compare_runs(run_dirs) -> pd.DataFrame:
    """Rows of accuracy / macro-F1 before and after correction for every run (and sweep point)."""
    rows = []
    for d in run_dirs:
        p = Path(d) / "metrics.json"
        if not p.is_file():
            raise InputError(f"{p} not found; pass run folders written by 'gaitml evaluate'.")
        m = json.loads(p.read_text())
        base = {
            "run": m["name"],
            "model": m["model_kind"],
            "features": m["feature_set"],
            "window_s": m["window_length_s"],
            "scheme": m["scheme"],
        }
        if "sweep" in m:
            for r in m["sweep"]:
                point = {k: v for k, v in r.items() if "." in k}
                row = dict(base)
                row.update(
                    {
                        "model": point.get("model.kind", base["model"]),
                        "features": point.get("features.set", base["features"]),
                        "window_s": point.get("windows.length_s", base["window_s"]),
                    }
                )
                row["point"] = ", ".join(f"{k}={v}" for k, v in point.items())
                row.update(
                    acc_before=r["accuracy_before"],
                    acc_after=r["accuracy_after"],
                    f1_before=r["macro_f1_before"],
                    f1_after=r["macro_f1_after"],
                    n_windows=r["n_windows"],
                )
                rows.append(row)
        else:
            rows.append(
                {
                    **base,
                    "point": "",
                    "acc_before": m["accuracy_before_correction"],
                    "acc_after": m["accuracy_after_correction"],
                    "f1_before": m["macro_f1_before_correction"],
                    "f1_after": m["macro_f1_after_correction"],
                    "n_windows": m["n_windows"],
                }
            )
    return pd.DataFrame(rows)


def _markdown(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in df.iterrows():
        out.append(
            "| " + " | ".join(f"{r[c]:.4f}" if isinstance(r[c], float) and c.startswith(("acc", "f1")) else str(r[c]) for c in cols) + " |"
        )
    return "\n".join(out)


def main(argv=None) -> int:  # pragma: no cover - thin CLI
    args = list(sys.argv[1:] if argv is None else argv)
    csv = None
    if "--csv" in args:
        i = args.index("--csv")
        csv = args[i + 1]
        del args[i : i + 2]
    df = compare_runs(args)
    print(_markdown(df))
    if csv:
        from gaitml.io import write_csv

        write_csv(csv, df)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
