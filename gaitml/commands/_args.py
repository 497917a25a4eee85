"""What the commands' option declarations share: registry-backed choices, the input options, the parser class.

Each command declares its options in ``gaitml/commands/<name>.py`` (``HELP`` and
``add_arguments(parser)``) beside its ``run(args)``; :mod:`gaitml.cli` only assembles them.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence

__all__ = [
    "REGISTRY_CHOICES",
    "STEP_DETECTORS",
    "ZUPT_DETECTORS",
    "Parser",
    "UsageError",
    "add_input_options",
    "choices",
    "step_detectors",
    "zupt_detectors",
    "heading_sources",
    "mode_sources",
    "mode_assignments",
    "formats",
    "feature_sets",
    "feature_frames",
]


class _Names(Sequence):
    """Choices read from a registry on first use, so that building the parser imports no algorithm.

    argparse reads choices only to check a given value and to format help or an
    error; the options that use them set a ``metavar`` so that nothing is read
    while the parser is built.
    """

    def __init__(self, load: Callable[[], object]):
        self._load = load
        self._names: tuple[str, ...] | None = None

    def _get(self) -> tuple[str, ...]:
        if self._names is None:
            self._names = tuple(self._load())
        return self._names

    def __getitem__(self, i):
        return self._get()[i]

    def __len__(self) -> int:
        return len(self._get())

    def __contains__(self, x) -> bool:
        return x in self._get()

    def __iter__(self):
        return iter(self._get())

    def __repr__(self) -> str:
        return repr(self._get())


def step_detectors():
    from gaitml.steps import detector_names

    return detector_names()


def zupt_detectors():
    from gaitml.zupt import DETECTORS

    return DETECTORS


def heading_sources():
    from gaitml.pdr import HEADING_SOURCES

    return HEADING_SOURCES


def gyro_bias_modes():
    from gaitml.pdr.attitude import GYRO_BIAS_MODES

    return GYRO_BIAS_MODES


def mode_sources():
    from gaitml.pdr import MODE_SOURCES

    return MODE_SOURCES


def mode_assignments():
    from gaitml.pdr.step_modes import MODE_ASSIGNMENTS

    return MODE_ASSIGNMENTS


def formats():
    from gaitml.io import FORMATS

    return FORMATS


def feature_sets():
    from gaitml.features import FEATURE_SETS
    from gaitml.features._catalogue import SUBSET_ALIASES

    return (*FEATURE_SETS, *SUBSET_ALIASES)


def feature_frames():
    from gaitml.features import FEATURE_FRAMES

    return FEATURE_FRAMES


#: Names of the step and zero-velocity detectors: lazy views of the registries.
STEP_DETECTORS = _Names(step_detectors)
ZUPT_DETECTORS = _Names(zupt_detectors)
#: The registry behind each option with fixed choices: ``{(command, option): names}``.
REGISTRY_CHOICES: dict[tuple[str, str], Sequence] = {}


def choices(command: str, option: str, load: Callable[[], object]) -> dict:
    """``add_argument`` keywords for an option whose choices come from a registry."""
    names = REGISTRY_CHOICES.setdefault((command, option), _Names(load))
    return {"choices": names, "metavar": option.lstrip("-").replace("-", "_").upper()}


class UsageError(Exception):
    """A bad command line: reported as one line (exit 2)."""


class Parser(argparse.ArgumentParser):
    """argparse with a one-line error (exit 2) instead of usage + message."""

    def error(self, message: str) -> None:  # noqa: D102
        raise UsageError(f"{message}; see '{self.prog} --help'.")


def add_input_options(p: argparse.ArgumentParser) -> None:
    """The options that say how to read INPUT (format, units, rate, columns), in their own help group."""
    g = p.add_argument_group("input")
    g.add_argument(
        "--format",
        **choices(p.prog.split()[-1], "--format", formats),
        help="input format: %(choices)s (default: detected from the content)",
    )
    g.add_argument("--sensor", choices=("left", "right"), default="left", help="foot of a two-sensor gaitmap file (default: left)")
    g.add_argument(
        "--sampling-rate-hz",
        type=float,
        help="resample to this uniform rate (Oxford default 100 Hz), or the rate of a file without a time base",
    )
    g.add_argument("--acc-unit", choices=("m/s^2", "g"), default="m/s^2", help="unit of a gaitml-csv's acc columns (default m/s^2)")
    g.add_argument("--gyr-unit", choices=("rad/s", "deg/s"), default="rad/s", help="unit of a gaitml-csv's gyr columns (default rad/s)")
    g.add_argument(
        "--columns",
        metavar="MAP",
        help="read any CSV by naming its columns: t=COL,acc_x=COL,acc_y=COL,acc_z=COL[,gyr_x=COL,gyr_y=COL,gyr_z=COL][,t_gyr=COL][,label=COL]",
    )
    g.add_argument("--time-unit", choices=("s", "ms", "us", "ns"), default="s", help="unit of the --columns time column (default s)")
