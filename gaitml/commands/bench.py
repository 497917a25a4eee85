"""`gaitml bench [--out DIR] [--quick]`: the throughput benchmarks of a source checkout (``benchmarks/``)."""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from gaitml.errors import NotAvailableError

#: The command's one-line description in ``gaitml --help``.
HELP = "throughput benchmarks against reference implementations"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml bench`` on its parser ``p``."""
    p.add_argument("--out", metavar="DIR", default="bench-out")
    p.add_argument("--quick", action="store_true", help="smaller inputs (a smoke run)")


def load_benchmarks(root: str | Path | None = None):
    """The top-level ``benchmarks`` package of the checkout this ``gaitml`` was imported from.

    Parameters
    ----------
    root : path, optional
        The checkout (default: the folder holding this ``gaitml`` package).

    Raises
    ------
    NotAvailableError
        When ``gaitml`` is installed without its source checkout (no ``benchmarks/`` beside ``gaitml/``).
    """
    root = Path(__file__).resolve().parents[2] if root is None else Path(root).resolve()
    if not (root / "benchmarks" / "__init__.py").is_file():
        raise NotAvailableError(
            f"gaitml bench needs a source checkout (no benchmarks/ folder in {root}); clone the repository, "
            "`pip install -e .` and run `gaitml bench` or `python -m benchmarks` from its root."
        )
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    mod = importlib.import_module("benchmarks")
    if Path(mod.__file__).resolve().parent != root / "benchmarks":
        raise NotAvailableError(
            f"another 'benchmarks' package ({mod.__file__}) shadows {root / 'benchmarks'}; run from the repository root."
        )
    return mod


def run(args) -> int:
    print(load_benchmarks().write_results(args.out, quick=args.quick))
    return 0
