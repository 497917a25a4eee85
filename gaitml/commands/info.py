"""`gaitml info INPUT [--json]`: what was read."""

from __future__ import annotations

from gaitml.commands._util import emit_json, read_kwargs
from gaitml.info import describe_path, format_text


def run(args) -> int:
    desc = describe_path(args.input, **read_kwargs(args))
    if args.json:
        emit_json(desc)
    else:
        print(format_text(desc))
    return 0
