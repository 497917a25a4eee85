"""Run a lab script with every tyrex motion capture read at one alignment: before/after figures of the refinement.

``gaitml.io.tyrex.read_tyrex_truth`` (and the names it is re-exported under) is replaced by the same function with
``align`` fixed, then the script's ``main`` runs with the remaining arguments:

    python -m experiments.scripts.with_align file experiments.scripts.tyrex_steps --data ../shared/data
    python -m experiments.scripts.with_align refine experiments.scripts.tyrex_steps --data ../shared/data
"""

from __future__ import annotations

import functools
import importlib
import sys


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if len(argv) < 2:
        print("usage: python -m experiments.scripts.with_align {refine|file} MODULE [ARGS...]", file=sys.stderr)
        return 2
    align, module, rest = argv[0], argv[1], argv[2:]
    import gaitml.io
    import gaitml.io.tyrex as tyrex

    if align not in tyrex.TYREX_ALIGN_MODES:
        print(f"align {align!r} is not one of {tyrex.TYREX_ALIGN_MODES}", file=sys.stderr)
        return 2
    fixed = functools.partial(tyrex.read_tyrex_truth, align=align)
    tyrex.read_tyrex_truth = fixed
    gaitml.io.read_tyrex_truth = fixed
    print(f"# tyrex motion capture read with align={align!r}", file=sys.stderr)
    mod = importlib.import_module(module)
    return int(mod.main(rest) or 0)


if __name__ == "__main__":
    raise SystemExit(main())
