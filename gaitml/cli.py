"""The ``gaitml`` command: argument parsing only; the work is done by library code.

Every subcommand of DESIGN sec. 5 is listed in :data:`COMMANDS`; its module
``gaitml/commands/<name>.py`` holds its one-line ``HELP``, its options
(``add_arguments(parser)``) and its handler ``run(args) -> int``. Exit status: 0 success,
2 bad input or arguments (one line on stderr naming the problem and the fix,
no traceback), 1 internal error.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import select
import signal
import sys
import traceback

from gaitml.commands._args import REGISTRY_CHOICES, STEP_DETECTORS, ZUPT_DETECTORS, Parser, UsageError
from gaitml.errors import GaitmlError

__all__ = ["COMMANDS", "main", "build_parser", "REGISTRY_CHOICES", "STEP_DETECTORS", "ZUPT_DETECTORS"]


#: The commands in the order ``gaitml --help`` lists them; each is ``gaitml/commands/<name>.py``.
COMMANDS = (
    "info",
    "split",
    "simulate",
    "steps",
    "zupt",
    "features",
    "train",
    "evaluate",
    "predict",
    "pdr",
    "model",
    "label",
    "segment",
    "demo",
    "bench",
)


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser (used by ``main`` and by the docs tests): each command's ``HELP`` and ``add_arguments``."""
    from gaitml import __version__

    parser = Parser(prog="gaitml", description="Smartphone gait, motion-mode recognition and PDR.")
    parser.add_argument("--version", action="version", version=f"gaitml {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for name in COMMANDS:
        module = importlib.import_module(f"gaitml.commands.{name}")
        module.add_arguments(sub.add_parser(name, help=module.HELP))
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            print("gaitml: error: no command given; see 'gaitml --help' for the commands.", file=sys.stderr)
            return 2
        from gaitml.commands._paths import check_outputs

        check_outputs(args)
        module = importlib.import_module(f"gaitml.commands.{args.command}")
        with _terminate_as_interrupt():
            return int(module.run(args) or 0)
    except UsageError as exc:
        print(f"gaitml: error: {exc}", file=sys.stderr)
        return 2
    except GaitmlError as exc:
        msg = " ".join(str(exc).split())
        print(f"gaitml: error: {msg}", file=sys.stderr)
        return 2
    except _Terminated as exc:
        print(f"gaitml: terminated by {signal.Signals(exc.signum).name}", file=sys.stderr)
        return 128 + exc.signum
    except KeyboardInterrupt:
        print("gaitml: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError as exc:
        if _stdout_closed():  # `gaitml ... | head`: the reader went away, not an error of ours
            return 0
        return _internal_error(exc)
    except (PermissionError, IsADirectoryError, NotADirectoryError, FileExistsError) as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(f"gaitml: error: {exc.strerror or type(exc).__name__}:{where}; check the path and its permissions.", file=sys.stderr)
        return 2
    except Exception as exc:  # an internal error: a bug to report
        return _internal_error(exc)


class _Terminated(BaseException):
    """SIGTERM or SIGHUP during a command: unwinds like KeyboardInterrupt so that every
    atomic write (gaitml.io._atomic) removes its temporary file on the way out."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


#: Signals that end a run cleanly, as SIGINT does (exit status 128 + the signal's number).
TERMINATING_SIGNALS = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


@contextlib.contextmanager
def _terminate_as_interrupt():
    """While a command runs, turn SIGTERM and SIGHUP into :class:`_Terminated` (main thread only)."""

    def handler(signum, _frame):
        raise _Terminated(signum)

    previous = {}
    try:
        for sig in TERMINATING_SIGNALS:
            previous[sig] = signal.signal(sig, handler)
    except ValueError:  # not the main thread: leave the signals alone
        pass
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _stdout_closed() -> bool:
    """Whether stdout is a pipe whose reading end was closed."""
    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLERR)
        return bool(poller.poll(0))
    except (OSError, ValueError, AttributeError):
        return False


def _internal_error(exc: BaseException) -> int:
    if os.environ.get("GAITML_DEBUG"):
        traceback.print_exception(exc)
    msg = " ".join(str(exc).split())
    print(f"gaitml: internal error: {type(exc).__name__}: {msg} (set GAITML_DEBUG=1 for the traceback; please report it)", file=sys.stderr)
    return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
