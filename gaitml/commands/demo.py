"""`gaitml demo [--out DIR]`: the main job end to end on the built-in simulator."""

from __future__ import annotations

from gaitml.demo import format_summary, run_demo


def run(args) -> int:
    summary = run_demo(args.out)
    print(format_summary(summary))
    return 0
