"""`gaitml bench` runs the benchmarks/ folder of a source checkout, and says so without one."""

from __future__ import annotations

from pathlib import Path

import pytest

from gaitml.commands.bench import load_benchmarks
from gaitml.errors import NotAvailableError

ROOT = Path(__file__).resolve().parents[2]


def test_the_checkout_benchmarks_are_found():
    mod = load_benchmarks()
    assert Path(mod.__file__).resolve() == ROOT / "benchmarks" / "__init__.py"
    assert mod.AREAS == ("features", "steps", "zupt", "models", "pdr", "simulate")


def test_without_a_checkout_the_error_is_one_line(tmp_path):
    with pytest.raises(NotAvailableError, match=r"gaitml bench needs a source checkout .*python -m benchmarks") as exc:
        load_benchmarks(tmp_path)
    assert "\n" not in str(exc.value)


def test_the_markdown_table_of_the_runner():
    import pandas as pd

    bench = load_benchmarks()
    df = pd.DataFrame(
        [{"area": "zupt", "name": "x", "n_items": 1000, "unit": "samples", "seconds": 0.5, "throughput_per_s": 2000.0, "note": "n"}]
    )
    for c in bench.COLUMNS:
        df[c] = df.get(c)
    md = bench.to_markdown(df, {"python": "3.11"})
    assert "Machine: python 3.11" in md and "| zupt | x | 1,000 | samples | 0.5 | 2,000 |  |  | n |" in md
