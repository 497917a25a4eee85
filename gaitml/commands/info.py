"""`gaitml info INPUT [--json]`: what was read."""

from __future__ import annotations

from gaitml.commands._util import emit_json
from gaitml.info import describe_path, format_text


def run(args) -> int:
    kwargs = {
        "format": args.format,
        "sensor": args.sensor,
        "sampling_rate_hz": args.sampling_rate_hz,
        "acc_unit": args.acc_unit,
        "gyr_unit": args.gyr_unit,
    }
    desc = describe_path(args.input, **kwargs)
    if args.json:
        emit_json(desc)
    else:
        print(format_text(desc))
    return 0
