"""Print the table of input classes x commands with each outcome.

Usage: ``PYTHONPATH=. python -m tests.hostile.table`` (about half a minute). Each cell is
``0`` (accepted, the right answer) or ``2`` (refused with one line), followed by ``!``
if the outcome broke the contract or differs from the class's declared outcome.
"""

from __future__ import annotations

import re
import sys
import tempfile
from pathlib import Path

from tests.hostile.corpus import RECORDING_CASES, RECORDING_COMMANDS
from tests.hostile.runner import check_contract, command_argv, run_cli


def main() -> int:
    bad = 0
    print("| class | expected | " + " | ".join(RECORDING_COMMANDS) + " | message (first refusal) |")
    print("|---|---|" + "---|" * len(RECORDING_COMMANDS) + "---|")
    with tempfile.TemporaryDirectory() as tmp:
        for case in RECORDING_CASES:
            d = Path(tmp) / case.name
            d.mkdir()
            path = case.make(d)
            cells, message = [], ""
            for command in RECORDING_COMMANDS:
                out = d / f"out-{command}"
                out.mkdir()
                argv = command_argv(command, path, out, case.args)
                code, stdout, stderr = run_cli(argv)
                mark = ""
                try:
                    js = check_contract(argv, code, stdout, stderr, case.outcome(command), out)
                    if js is not None and case.check is not None:
                        case.check(command, js, None)
                except AssertionError:
                    mark, bad = "!", bad + 1
                cells.append(f"{code}{mark}")
                if code == 2 and not message:
                    message = re.sub(r"/\S+/", "", stderr.strip().removeprefix("gaitml: error: "))[:110].replace("|", "/")
            expected = "0" if case.expect == "ok" else "2"
            if case.per_command:
                expected += " (" + ", ".join(f"{k} {'0' if v == 'ok' else '2'}" for k, v in case.per_command.items()) + ")"
            opts = f" `{' '.join(case.args)}`" if case.args else ""
            print(f"| {case.name}{opts} | {expected} | " + " | ".join(cells) + f" | {message} |")
    print(f"\n{len(RECORDING_CASES)} classes x {len(RECORDING_COMMANDS)} commands, {bad} not clean", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
