"""`gaitml bench [--out DIR] [--quick]`: throughput of every component against a reference."""

from __future__ import annotations

import importlib
import os
import platform
from pathlib import Path

import pandas as pd

from gaitml.bench import AREAS
from gaitml.commands._util import log
from gaitml.io import write_csv, write_json, write_text


def machine_info() -> dict:
    """The machine the numbers were measured on."""
    import numpy as np

    info = {
        "python": platform.python_version(),
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "numpy": np.__version__,
    }
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    info["cpu"] = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return info


def run_benchmarks(quick: bool = False) -> pd.DataFrame:
    """Run every available benchmark module; areas not built yet are skipped with a note."""
    rows = []
    for area in AREAS:
        try:
            mod = importlib.import_module(f"gaitml.bench.{area}")
        except ModuleNotFoundError as exc:
            if exc.name and exc.name.startswith("gaitml.bench"):
                continue
            raise
        log(f"bench: {area} ...")
        rows.extend(mod.run(quick=quick))
    cols = ["area", "name", "n_items", "unit", "seconds", "throughput_per_s", "reference_seconds", "ratio", "note"]
    df = pd.DataFrame(rows)
    for c in cols:
        if c not in df.columns:
            df[c] = None
    return df[cols + [c for c in df.columns if c not in cols]]


def to_markdown(df: pd.DataFrame, info: dict) -> str:
    lines = ["# gaitml bench", "", "Machine: " + ", ".join(f"{k} {v}" for k, v in info.items()), ""]
    lines.append("| area | benchmark | items | unit | seconds | throughput /s | reference s | ratio | note |")
    lines.append("|---|---|---:|---|---:|---:|---:|---:|---|")
    for r in df.itertuples(index=False):
        ref = "" if pd.isna(r.reference_seconds) else f"{r.reference_seconds:.4g}"
        ratio = "" if pd.isna(r.ratio) else f"{r.ratio:.1f}x"
        lines.append(
            f"| {r.area} | {r.name} | {int(r.n_items):,} | {r.unit} | {r.seconds:.4g} | {r.throughput_per_s:,.0f} | {ref} | {ratio} | {r.note or ''} |"
        )
    return "\n".join(lines) + "\n"


def run(args) -> int:
    info = machine_info()
    df = run_benchmarks(quick=args.quick)
    md = to_markdown(df, info)
    out = Path(args.out)
    write_csv(out / "bench.csv", df)
    write_json(out / "bench.json", {"machine": info, "rows": df.to_dict("records")})
    write_text(out / "bench.md", md)
    print(md)
    log(f"bench: wrote {out / 'bench.md'}")
    return 0
