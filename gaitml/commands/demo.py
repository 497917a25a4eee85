"""`gaitml demo [--out DIR]`: the main job end to end on the built-in simulator."""

from __future__ import annotations

import argparse

#: The command's one-line description in ``gaitml --help``.
HELP = "the main job end to end on simulated data"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml demo`` on its parser ``p``."""
    p.add_argument("--out", metavar="DIR", default="demo-out")


def run(args) -> int:
    from gaitml.demo import format_summary, run_demo

    summary = run_demo(args.out)
    print(format_summary(summary))
    return 0
