"""Benchmarks behind ``gaitml bench``: one module per area, each ``run(quick) -> list[dict]``.

Every row measures our implementation and, where there is one, a plain reference
implementation of the same computation in the same process (``ratio`` =
reference time / our time), so the figures are comparable across machines.

This folder is not part of the installed package: run it from a source checkout,
``gaitml bench [--quick] [--out DIR]`` or ``python -m benchmarks [--quick] [--out DIR]``
from the repository root. Targets and measured figures: ``benchmarks/README.md``.
"""

from __future__ import annotations

import importlib
import os
import platform
import sys
from pathlib import Path

import pandas as pd

__all__ = ["AREAS", "machine_info", "run_benchmarks", "to_markdown", "write_results", "main"]

AREAS = ("features", "steps", "zupt", "models", "pdr", "simulate")
COLUMNS = ["area", "name", "n_items", "unit", "seconds", "throughput_per_s", "reference_seconds", "ratio", "note"]


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


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


def run_benchmarks(quick: bool = False, areas=AREAS) -> pd.DataFrame:
    """Run the benchmark module of every area in ``areas``; one row per measurement."""
    rows = []
    for area in areas:
        mod = importlib.import_module(f"benchmarks.{area}")
        _log(f"bench: {area} ...")
        rows.extend(mod.run(quick=quick))
    df = pd.DataFrame(rows)
    for c in COLUMNS:
        if c not in df.columns:
            df[c] = None
    return df[COLUMNS + [c for c in df.columns if c not in COLUMNS]]


def to_markdown(df: pd.DataFrame, info: dict) -> str:
    """The results table as markdown, headed by the machine description."""
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


def write_results(out: str | Path, quick: bool = False) -> str:
    """Run every benchmark and write ``bench.csv``, ``bench.json`` and ``bench.md`` into ``out``; returns the markdown."""
    from gaitml.io import write_csv, write_json, write_text

    info = machine_info()
    df = run_benchmarks(quick=quick)
    md = to_markdown(df, info)
    out = Path(out)
    write_csv(out / "bench.csv", df)
    write_json(out / "bench.json", {"machine": info, "rows": df.to_dict("records")})
    write_text(out / "bench.md", md)
    _log(f"bench: wrote {out / 'bench.md'}")
    return md


def main(argv: list[str] | None = None) -> int:
    """``python -m benchmarks [--quick] [--out DIR]``."""
    import argparse

    p = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    p.add_argument("--out", metavar="DIR", default="bench-out")
    p.add_argument("--quick", action="store_true", help="smaller inputs (a smoke run)")
    a = p.parse_args(argv)
    print(write_results(a.out, quick=a.quick))
    return 0
