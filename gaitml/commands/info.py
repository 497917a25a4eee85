"""`gaitml info INPUT [--json]`: what was read."""

from __future__ import annotations

import argparse

from gaitml.commands._args import add_input_options
from gaitml.commands._util import emit_json, read_kwargs

#: The command's one-line description in ``gaitml --help``.
HELP = "describe a recording or data set"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml info`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_input_options(p)


def run(args) -> int:
    from gaitml.info import describe_path, format_text

    desc = describe_path(args.input, **read_kwargs(args))
    if args.json:
        emit_json(desc)
    else:
        print(format_text(desc))
    return 0
